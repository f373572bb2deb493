//! `motionhdl trace estop`: the e-stop chain opening in the middle of a
//! move (docs/safety_io.md, "E-stop"; the 4-axis S-curve version is
//! `tests/system.rs`).

use super::limit_stop::creep;
use super::system::{two_axes, DRIVE_LATENCY};
use crate::trace::Trace;
use motionhdl_model::safety_io::ESTOP_LATENCY;
use motionhdl_model::Config;

/// Two axes creep, the chain opens: HALT stops both within ESTOP_LATENCY
/// edges, the drives are disabled, the outputs take their safe state,
/// IRQ falls; the chain closes and firmware clears the latch, the drives
/// stay off until enabled.
pub fn trace(config: &Config) -> Trace {
    let mut sys = two_axes(config, |c| c);
    sys.record_scenario(config, "estop");
    sys.write("SAFETY", None, "ENABLE", 3);
    sys.write("SAFETY", None, "GPO_SAFE", 0x00f0);
    sys.write("SAFETY", None, "GPO_VALUE", 0x000f);
    sys.write("SAFETY", None, "CAUSE_MASK", 1);
    let (segments, _) = creep(100);
    for axis in 0..2 {
        for s in &segments {
            sys.push(axis, s);
        }
    }
    sys.write("PULSE", None, "RUN", 3);
    sys.idle(3_000);
    sys.mark("e-stop");
    sys.estop_ok = false;
    sys.idle(u64::from(ESTOP_LATENCY) + 2 + DRIVE_LATENCY as u64);
    let stopped: Vec<i32> = sys.drives.iter().map(|d| d.position).collect();
    assert!(
        stopped.iter().all(|&p| p > 0 && p < 100),
        "estop trace: mid-move {stopped:?}"
    );
    assert_eq!(sys.drive_enable(), 0, "estop trace: drives off");
    assert_eq!(sys.gpo().0, 0x00f0, "estop trace: outputs safe");
    sys.idle(2_000);
    let later: Vec<i32> = sys.drives.iter().map(|d| d.position).collect();
    assert_eq!(later, stopped, "estop trace: no step after the latency");
    assert!(!sys.irq(), "estop trace: IRQ low");
    sys.estop_ok = true;
    sys.idle(3);
    sys.mark("CLEAR");
    sys.write("SAFETY", None, "CLEAR", 1);
    sys.write("SAFETY", None, "CAUSE", 1);
    sys.idle(200);
    assert!(sys.irq(), "estop trace: cleared, IRQ released");
    assert_eq!(sys.drive_enable(), 0, "estop trace: drives stay off");
    sys.take_trace().expect("recording")
}
