//! The whole controller with a watchdog firmware stops feeding
//! (docs/safety_io.md, "Watchdog", "HALT and ENABLE", "General-purpose
//! outputs"): it bites TIMEOUT + 1 clocks after the last feed, every axis
//! stops with its count exact, the drives are disabled, the outputs take
//! their safe state and keep it until firmware writes them, and the
//! counter bank keeps counting a shaft turned by hand.

use motionhdl_model::Config;
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};
use motionhdl_testbench::checks::motion_controller::watchdog_bite::{
    run_into_bite, OPEN_DRAIN, RUNNING, SAFE, TIMEOUT,
};

/// The output pins for GPO_VALUE `value`: push-pull drives it, open-drain
/// drives 0 and releases 1.
fn pins(value: u32) -> (u32, u32) {
    (
        value & !OPEN_DRAIN & 0xffff,
        (!OPEN_DRAIN | !value) & 0xffff,
    )
}

#[test]
fn an_unfed_watchdog_bites_and_stops_everything_but_the_counters() {
    let mut sys = System::<4>::on(Engine::for_scenarios(), &Config::default());
    sys.setup();
    let bite = run_into_bite(&mut sys);
    // The last feed's write ends a few clocks after the bus op began; the
    // bite follows TIMEOUT + 1 edges after it and ENABLE drops with it.
    let waited = bite.disabled_at - bite.last_feed;
    assert!(
        (u64::from(TIMEOUT) - 10..=u64::from(TIMEOUT) + 2).contains(&waited),
        "bit {waited} clocks after the last feed, TIMEOUT {TIMEOUT}"
    );
    for (i, (&at, &later)) in bite.at_bite.iter().zip(&bite.later).enumerate() {
        assert!(at > 0 && at < 200, "axis {i} was mid-move: {at}");
        assert_eq!(later, at, "axis {i}: no step after the bite");
    }
    assert_eq!(sys.drive_enable(), 0);
    assert!(!sys.irq(), "CAUSE.WATCHDOG unmasked: the IRQ pin is low");
    let status = sys.read("SAFETY", None, "STATUS");
    assert_eq!(
        status & 0b1100,
        0b0100,
        "BITTEN set, ARMED clear: {status:#x}"
    );
    assert_eq!(sys.read("SAFETY", None, "CAUSE"), 2);
    assert_eq!(sys.read("PULSE", None, "RUN"), 0, "RUN cleared");
    assert_eq!(sys.gpo(), pins(SAFE), "outputs in their safe state");
    assert_ne!(pins(SAFE), pins(RUNNING));
    // A write while bitten is lost.
    sys.write("SAFETY", None, "GPO_VALUE", RUNNING);
    assert_eq!(sys.read("SAFETY", None, "GPO_VALUE"), SAFE);
    // The counters keep counting: a shaft turned by hand is followed.
    for _ in 0..25 {
        sys.drives[2].position -= 1;
        sys.idle(10);
    }
    for (i, (count, position)) in sys.positions().into_iter().enumerate() {
        assert_eq!(count, sys.drives[i].position, "axis {i}: COUNT = shaft");
        let commanded = bite.later[i];
        assert_eq!(position, commanded, "axis {i}: POSITION = steps sent");
    }
    // Cleared, the outputs hold their safe state until firmware writes.
    sys.write("SAFETY", None, "CLEAR", 2);
    assert_eq!(sys.read("SAFETY", None, "STATUS") & 0b100, 0);
    assert_eq!(sys.gpo(), pins(SAFE));
    sys.write("SAFETY", None, "GPO_VALUE", RUNNING);
    assert_eq!(sys.gpo(), pins(RUNNING));
}
