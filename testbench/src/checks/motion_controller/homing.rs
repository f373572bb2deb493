//! Homing in the whole controller (docs/safety_io.md, "Home capture"):
//! the firmware crate's sequence ([`motionhdl_firmware::homing`]) driven
//! over the FSMC bus, as the MCU runs it, against a simulated HOME switch
//! and encoder index; and `motionhdl trace homing`.

use super::limit_stop::fast_filter_axes;
use super::system::System;
use crate::trace::Trace;
use motionhdl_firmware::homing::{Home, Homing, HomingAxis, HomingParams, Poll};
use motionhdl_model::pulse_generator::Segment;
use motionhdl_model::Config;

/// One axis of the system as the homing sequence sees it: each method is
/// the register accesses firmware makes; `poll_every` clocks pass before
/// each STATUS poll (the firmware busy elsewhere).
pub struct BusAxis<'a, const N: usize> {
    pub sys: &'a mut System<N>,
    pub axis: u32,
    pub poll_every: u64,
}

impl<const N: usize> BusAxis<'_, N> {
    fn bit(&self) -> u32 {
        1 << self.axis
    }

    /// Read-modify-write of a SAFETY or PULSE register shared by the axes.
    fn update(&mut self, block: &str, reg: &str, set: bool) {
        let old = self.sys.read(block, None, reg);
        let new = if set {
            old | self.bit()
        } else {
            old & !self.bit()
        };
        self.sys.write(block, None, reg, new);
    }

    fn field(&self, block: &str, array: &str, reg: &str, field: &str) -> u32 {
        let b = self.sys.map().block(block);
        let lsb = b.array(array).register(reg).field(field).lsb;
        1 << lsb
    }
}

impl<const N: usize> HomingAxis for BusAxis<'_, N> {
    fn arm_home(&mut self) {
        self.update("SAFETY", "HOME_CTRL", true);
        self.update("SAFETY", "HOME_STOP", true);
    }
    fn release_home(&mut self) {
        self.update("SAFETY", "HOME_STOP", false);
    }
    fn start_move(&mut self, steps: i32, period: u32) {
        let rate = ((1i64 << 32) / i64::from(period)) * i64::from(steps.signum());
        let segment = Segment {
            steps: steps.unsigned_abs(),
            rate: rate as i32,
            accel: 0,
            jerk: 0,
        };
        self.sys.push(self.axis, &segment);
        self.update("PULSE", "RUN", true);
    }
    fn stop(&mut self) {
        self.update("PULSE", "RUN", false);
    }
    fn moving(&mut self) -> bool {
        self.sys.idle(self.poll_every);
        let s = self.sys.read("PULSE", Some(self.axis), "STATUS");
        let status = self.sys.map().block("PULSE").array("AX").register("STATUS");
        ["BUSY", "MOVING", "FIFO_LEVEL"]
            .iter()
            .any(|f| status.field(f).get(s) != 0)
    }
    fn home_seen(&mut self) -> bool {
        self.sys.read("SAFETY", None, "HOME_ALARM_CAUSE") & self.bit() != 0
    }
    fn clear_home(&mut self) {
        self.sys
            .write("SAFETY", None, "HOME_ALARM_CAUSE", self.bit());
    }
    fn on_switch(&mut self) -> bool {
        self.sys.read("SAFETY", None, "HOME_ALARM_INPUTS") & self.bit() != 0
    }
    fn captured(&mut self) -> (i32, i32) {
        (
            self.sys.read("PULSE", Some(self.axis), "HOME_POSITION") as i32,
            self.sys.read("COUNTER", Some(self.axis), "HOME_COUNT") as i32,
        )
    }
    fn arm_index(&mut self) {
        let ctrl = self.sys.read("COUNTER", Some(self.axis), "CTRL")
            | self.field("COUNTER", "CH", "CTRL", "IDX_LATCH")
            | self.field("COUNTER", "CH", "CTRL", "IDX_ONESHOT");
        self.sys.write("COUNTER", Some(self.axis), "CTRL", ctrl);
        let arm = self.field("COUNTER", "CH", "CMD", "ARM");
        self.sys.write("COUNTER", Some(self.axis), "CMD", arm);
    }
    fn index(&mut self) -> Option<i32> {
        self.sys.write("COUNTER", None, "SNAPSHOT", 0);
        let status = self.sys.read("COUNTER", Some(self.axis), "STATUS");
        let armed = self.field("COUNTER", "CH", "STATUS", "ARMED");
        (status & armed == 0).then(|| self.sys.read("COUNTER", Some(self.axis), "INDEX") as i32)
    }
}

/// Homes `axis` of a set-up system with `params`, polling every
/// `poll_every` clocks; the result, or the failure as text.
pub fn home<const N: usize>(
    sys: &mut System<N>,
    axis: u32,
    params: HomingParams,
    poll_every: u64,
) -> Result<Home, String> {
    let mut homing = Homing::new(params).map_err(|e| format!("{e:?}"))?;
    let mut bus = BusAxis {
        sys,
        axis,
        poll_every,
    };
    loop {
        match homing.poll(&mut bus) {
            Poll::Busy => {}
            Poll::Done(home) => return Ok(home),
            Poll::Failed(e) => return Err(format!("axis {axis}: {e:?}")),
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
    let (mut sys, _) = fast_filter_axes(config);
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
