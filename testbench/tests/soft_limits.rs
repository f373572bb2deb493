//! Soft limits in the whole controller (docs/safety_io.md, "Soft
//! limits"): an axis moving past SOFT_MAX or SOFT_MIN stops within the
//! documented latency, sets its cause and the IRQ, refuses steps further
//! out, moves back in, and after a clear moves on; a disabled soft limit
//! stops nothing.

use motionhdl_firmware::scurve_segments::{self, EngineLimits};
use motionhdl_model::machine_inputs::SOFT_LIMIT_LATENCY;
use motionhdl_model::pulse_generator::Segment;
use motionhdl_model::Config;
use motionhdl_testbench::checks::motion_controller::limit_stop::{creep, run};
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};

const CLOCK_HZ: u32 = 50_000_000;

fn system() -> System<2> {
    let mut sys = System::<2>::on(
        Engine::for_scenarios(),
        &Config::new(2, 28, u64::from(CLOCK_HZ)).unwrap(),
    );
    sys.setup();
    sys
}

/// SOFT_MIN and SOFT_MAX of `axis`, then its soft limits on (both
/// directions) and on the IRQ.
fn limits(sys: &mut System<2>, axis: u32, min: i32, max: i32) {
    sys.write("PULSE", Some(axis), "SOFT_MIN", min as u32);
    sys.write("PULSE", Some(axis), "SOFT_MAX", max as u32);
    let both = 1 << axis | 1 << (axis + 16);
    sys.write("SAFETY", None, "SOFT_LIMIT_CTRL", both);
    sys.write("SAFETY", None, "SOFT_LIMIT_MASK", both);
}

fn position(sys: &mut System<2>, axis: usize) -> i32 {
    sys.positions()[axis].1
}

/// An S-curve to `target` steps at up to 2·10^6 steps/s (one step per 25
/// clocks).
fn plan(target: i64) -> (Vec<Segment>, u64) {
    let lim = EngineLimits::from_physical(2e6, 4e9, 8e13, f64::from(CLOCK_HZ));
    let p = scurve_segments::plan(target, lim).unwrap();
    (p.segments.to_vec(), p.clocks)
}

#[test]
fn an_axis_stops_at_its_soft_limits_and_moves_back_inside() {
    let mut sys = system();
    limits(&mut sys, 0, -50, 400);
    assert_eq!(sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"), 0);
    assert!(sys.irq(), "inside both limits: nothing set");
    assert_eq!(sys.read("PULSE", Some(0), "SOFT_MIN"), -50i32 as u32);

    // From POSITION reaching the limit at edge p, no step starts from edge
    // p + SOFT_LIMIT_LATENCY on; steps start 4 clocks apart at least
    // (STEP_LEN + STEP_SPACE), so at most one more goes out.
    assert_eq!(SOFT_LIMIT_LATENCY, 3);
    run(&mut sys, 0, &plan(1_000));
    let stopped = position(&mut sys, 0);
    assert!((400..=401).contains(&stopped), "stopped at {stopped}");
    assert_eq!(sys.drives[0].position, stopped, "the shaft followed");
    assert_eq!(
        sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"),
        1,
        "MAX of axis 0"
    );
    assert!(!sys.irq(), "the unmasked cause pulls IRQ low");
    assert_eq!(sys.read("PULSE", None, "RUN") & 1, 0, "RUN cleared");

    // Further out: refused. A clear while at the limit does not release.
    run(&mut sys, 0, &creep(20));
    assert_eq!(position(&mut sys, 0), stopped, "no step past SOFT_MAX");
    sys.write("SAFETY", None, "SOFT_LIMIT_CAUSE", 1);
    assert_eq!(sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"), 1);

    // Back inside, clear, on again; then down into SOFT_MIN.
    run(&mut sys, 0, &creep(-100));
    assert_eq!(position(&mut sys, 0), stopped - 100);
    sys.write("SAFETY", None, "SOFT_LIMIT_CAUSE", 1);
    assert_eq!(sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"), 0);
    assert!(sys.irq(), "cleared: IRQ released");
    run(&mut sys, 0, &creep(-600));
    let low = position(&mut sys, 0);
    assert!((-51..=-50).contains(&low), "stopped at {low}");
    assert_eq!(sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"), 1 << 16, "MIN");
    run(&mut sys, 0, &creep(30));
    assert_eq!(position(&mut sys, 0), low + 30, "up is allowed");
    let counts = sys.positions();
    assert_eq!(counts[0].0, low + 30, "COUNT follows");
}

#[test]
fn a_disabled_soft_limit_stops_nothing_and_sets_nothing() {
    let mut sys = system();
    limits(&mut sys, 0, -50, 100);
    sys.write("PULSE", Some(1), "SOFT_MAX", 100);
    // Axis 1's limits are off: it runs through its SOFT_MAX.
    run(&mut sys, 1, &creep(150));
    assert_eq!(position(&mut sys, 1), 150);
    assert_eq!(sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"), 0);
    // Axis 0's MAX turned off again: it runs through too.
    sys.write("SAFETY", None, "SOFT_LIMIT_CTRL", 1 << 16);
    run(&mut sys, 0, &creep(150));
    assert_eq!(position(&mut sys, 0), 150);
    assert_eq!(sys.read("SAFETY", None, "SOFT_LIMIT_CAUSE"), 0);
}
