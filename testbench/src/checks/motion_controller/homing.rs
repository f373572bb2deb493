//! Homing in the whole controller (docs/safety_io.md, "Home capture"):
//! the firmware crate's sequence ([`motionhdl_firmware::homing`]) through
//! the firmware driver ([`motionhdl_driver`]) over the FSMC bus, as the MCU
//! runs it, against a simulated HOME switch and encoder index; and
//! `motionhdl trace homing`.

use super::limit_stop::fast_filter_axes;
use super::system::{Engine, System};
use crate::trace::Trace;
use motionhdl_driver::Card;
use motionhdl_firmware::homing::{Home, Homing, HomingParams};
use motionhdl_model::Config;

/// Homes `axis` of a set-up system with `params`, polling every
/// `poll_every` clocks; the result, or the failure as text.
pub fn home<const N: usize>(
    sys: &mut System<N>,
    axis: u32,
    params: HomingParams,
    poll_every: u64,
) -> Result<Home, String> {
    let mut homing = Homing::new(params).map_err(|e| format!("{e:?}"))?;
    let mut card = Card::new(sys);
    loop {
        card.bus().idle(poll_every);
        match card.home_poll(&mut homing, axis) {
            Ok(None) => {}
            Ok(Some(home)) => return Ok(home),
            Err(e) => return Err(format!("axis {axis}: {e:?}")),
        }
    }
}

/// Where the trace's switch and index sit on axis 0's shaft.
pub const TRACE_SWITCH: i32 = 60;
pub const TRACE_INDEX_EVERY: i32 = 25;

/// The trace's homing parameters: search toward +, 200 steps at most.
pub fn trace_params() -> HomingParams {
    HomingParams {
        toward: 1,
        fast_period: 60,
        slow_period: 400,
        max_travel: 200,
        backoff: 10,
        index: true,
    }
}

/// `motionhdl trace homing`: axis 0 (two axes, a 1 µs input filter) homes
/// against a HOME switch at shaft position 60 with an index every 25
/// steps: fast search, back-off, slow search (HOME_POSITION and
/// HOME_COUNT capture the switch's edge), then on to the index at 75.
pub fn trace(config: &Config) -> Trace {
    let (mut sys, _) = fast_filter_axes(Engine::RustHdl, config);
    sys.home_at[0] = Some(TRACE_SWITCH);
    sys.index_every[0] = Some(TRACE_INDEX_EVERY);
    sys.idle(100);
    sys.record_scenario(config, "homing");
    let found = home(&mut sys, 0, trace_params(), 200).expect("homing trace");
    assert_eq!(found.index, Some(75), "homing trace: {found:?}");
    let fast = sys.mark_edge("axis0.home", 1, 0, "fast search reaches HOME");
    let off = sys.mark_edge("axis0.home", 0, fast, "backed off HOME");
    let slow = sys.mark_edge("axis0.home", 1, off, "slow search reaches HOME");
    sys.mark_edge("axis0.enc_z", 1, slow, "index: homed");
    sys.take_trace().expect("recording")
}
