//! Homing in the whole controller (docs/safety_io.md, "Home capture"): the
//! firmware crate's sequence runs over the FSMC bus against a simulated
//! HOME switch; HOME_POSITION and HOME_COUNT hold the switch's position
//! within the documented filter delay, the encoder index after it is
//! latched, and a missing switch is an error with the travel exact.

use motionhdl_firmware::homing::HomingParams;
use motionhdl_model::machine_inputs::{FILTER_TICKS, LIMIT_LATENCY};
use motionhdl_model::Config;
use motionhdl_testbench::checks::motion_controller::homing::home;
use motionhdl_testbench::checks::motion_controller::limit_stop::{creep, fast_filter_axes, run};
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};

const CLOCK_HZ: u32 = 50_000_000;

/// Two axes with a 1 µs input filter, set up; the filter's tick.
fn system() -> (System<2>, u32) {
    fast_filter_axes(
        Engine::for_scenarios(),
        &Config::new(2, 28, u64::from(CLOCK_HZ)).unwrap(),
    )
}

fn params(index: bool) -> HomingParams {
    HomingParams {
        toward: 1,
        fast_period: 50,
        slow_period: 500,
        max_travel: 2_000,
        backoff: 20,
        index,
    }
}

#[test]
fn homing_captures_the_switch_within_the_filter_delay() {
    let (mut sys, tick) = system();
    // Start away from 0 so a capture of the wrong register shows.
    run(&mut sys, 0, &creep(-137));
    let switch = 300;
    sys.home_at[0] = Some(switch);
    let found = home(&mut sys, 0, params(false), 300).expect("homing");
    // From the shaft reaching the switch to the capture: 2 synchroniser
    // edges, at most FILTER_TICKS ticks, the cause's edge; the steps
    // emitted meanwhile at the slow rate, plus those on their way to the
    // shaft (2 pin registers and the drive's 3 clocks).
    let latency = 2 + FILTER_TICKS * tick + LIMIT_LATENCY + 2 + 3;
    let bound = latency.div_ceil(params(false).slow_period) as i32;
    assert!(
        switch <= found.count && found.count <= found.position && found.position <= switch + bound,
        "switch {switch}, captured {found:?}, bound {bound} steps"
    );
    assert_eq!(found.index, None);
    // The slow search stopped on the edge: the shaft stands at the
    // capture (and the sequence released HOME_STOP).
    let shaft = sys.drives[0].position;
    assert!(
        (found.position..=found.position + 1).contains(&shaft),
        "shaft {shaft}, captured {found:?}"
    );
    assert_eq!(sys.read("SAFETY", None, "HOME_STOP"), 0);
    assert_eq!(sys.drives[1].position, 0, "axis 1 untouched");
}

#[test]
fn index_homing_latches_the_first_index_after_the_switch() {
    let (mut sys, _) = system();
    sys.home_at[0] = Some(300);
    sys.index_every[0] = Some(128);
    let found = home(&mut sys, 0, params(true), 300).expect("homing");
    assert_eq!(found.index, Some(384), "{found:?}");
    let shaft = sys.drives[0].position;
    assert!(
        (384..=386).contains(&shaft),
        "stopped near the index: {shaft}"
    );
}

#[test]
fn starting_on_the_switch_backs_off_and_finds_its_edge() {
    let (mut sys, _) = system();
    sys.home_at[0] = Some(-40);
    let found = home(&mut sys, 0, params(false), 300).expect("homing");
    assert!((-40..=-39).contains(&found.position), "{found:?}");
}

#[test]
fn no_switch_is_an_error_after_exactly_the_travel() {
    let (mut sys, _) = system();
    let e = home(&mut sys, 0, params(false), 2_000).unwrap_err();
    assert!(e.contains("NotFound"), "{e}");
    let p = sys.positions();
    assert_eq!(p[0], (2_000, 2_000), "the fast search ran max_travel steps");
}

#[test]
fn a_move_through_the_switch_captures_its_edge_on_the_fly() {
    let (mut sys, tick) = system();
    let switch = 300;
    sys.home_at[0] = Some(switch);
    // HOME on, no stop on home: the axis runs on through the switch.
    sys.write("SAFETY", None, "HOME_CTRL", 1);
    let (segments, clocks) = creep(600);
    run(&mut sys, 0, &(segments, clocks));
    assert_eq!(sys.drives[0].position, 600, "HOME stopped nothing");
    assert_eq!(sys.read("SAFETY", None, "HOME_ALARM_CAUSE"), 1);
    let position = sys.read("PULSE", Some(0), "HOME_POSITION") as i32;
    let count = sys.read("COUNTER", Some(0), "HOME_COUNT") as i32;
    // One step per 100 clocks; the latency as in the test above.
    let latency = 2 + FILTER_TICKS * tick + LIMIT_LATENCY + 2 + 3;
    let bound = latency.div_ceil(100) as i32;
    assert!(
        switch <= count && count <= position && position <= switch + bound,
        "switch {switch}: HOME_POSITION {position}, HOME_COUNT {count}, bound {bound}"
    );
    // Axis 1 saw no home event: its registers stay 0.
    assert_eq!(sys.read("PULSE", Some(1), "HOME_POSITION"), 0);
    assert_eq!(sys.read("COUNTER", Some(1), "HOME_COUNT"), 0);
}

#[test]
fn an_index_pulse_is_a_counter_event_on_the_irq() {
    let (mut sys, _) = system();
    // Off the index at 0 first, then the encoders get their index.
    run(&mut sys, 1, &creep(10));
    sys.index_every[1] = Some(64);
    sys.write("SAFETY", None, "COUNTER_MASK", 1 << 17);
    run(&mut sys, 0, &creep(100));
    assert_eq!(
        sys.read("SAFETY", None, "COUNTER_CAUSE"),
        0,
        "axis 0 has no index"
    );
    assert!(sys.irq());
    run(&mut sys, 1, &creep(70));
    assert_eq!(
        sys.read("SAFETY", None, "COUNTER_CAUSE"),
        1 << 17,
        "INDEX of channel 1"
    );
    assert!(!sys.irq(), "the unmasked cause pulls IRQ low");
    // An edge: clearing the cause while SEEN stays set keeps it clear;
    // after CMD.CLEAR_STATUS the next index sets it again.
    sys.write("SAFETY", None, "COUNTER_CAUSE", 1 << 17);
    run(&mut sys, 1, &creep(64));
    assert_eq!(
        sys.read("SAFETY", None, "COUNTER_CAUSE"),
        0,
        "SEEN still set"
    );
    assert!(sys.irq());
    let clear_status = sys
        .map()
        .block("COUNTER")
        .array("CH")
        .register("CMD")
        .field("CLEAR_STATUS")
        .lsb;
    sys.write("COUNTER", Some(1), "CMD", 1 << clear_status);
    run(&mut sys, 1, &creep(64));
    assert_eq!(sys.read("SAFETY", None, "COUNTER_CAUSE"), 1 << 17);
}
