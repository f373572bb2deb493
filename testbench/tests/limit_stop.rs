//! The whole controller runs into a limit switch (docs/safety_io.md,
//! "Direction stops"): the axis stops within the documented latency with
//! its count exact, the other axis finishes its move, a move further into
//! the switch is refused, a move away from it runs, and after a clear the
//! axis moves both ways again; with AX.DECEL set the axis brakes to rest
//! past the switch within v²/2a and is then held the same way.

use motionhdl_firmware::scurve_segments::{self, EngineLimits};
use motionhdl_model::machine_inputs::{FILTER_TICKS, LIMIT_LATENCY};
use motionhdl_model::pulse_generator::Segment;
use motionhdl_model::Config;
use motionhdl_testbench::checks::motion_controller::limit_stop::{creep, fast_filter_axes, run};
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};
use motionhdl_testbench::checks::pulse_bank::braking::brake_steps_bound;

const CLOCK_HZ: u32 = 50_000_000;
/// Steps per second at the top of every move here.
const VELOCITY: f64 = 2e6;

/// An S-curve's segments and clocks.
fn plan(target: i64) -> (Vec<Segment>, u64) {
    let lim = EngineLimits::from_physical(VELOCITY, 4e9, 8e13, f64::from(CLOCK_HZ));
    let p = scurve_segments::plan(target, lim).unwrap();
    (p.segments.to_vec(), p.clocks)
}

/// Two axes at CLOCK_HZ with a 1 µs input filter, set up, and the
/// filter's tick in clocks.
fn two_axes_with_fast_filter() -> (System<2>, u32) {
    fast_filter_axes(
        Engine::for_scenarios(),
        &Config::new(2, 28, u64::from(CLOCK_HZ)).unwrap(),
    )
}

fn shaft(sys: &System<2>, axis: usize) -> i32 {
    sys.drives[axis].position
}

/// COUNT and POSITION of every axis equal its shaft.
fn counts_are_exact(sys: &mut System<2>) {
    let shafts: Vec<i32> = (0..2).map(|i| shaft(sys, i)).collect();
    for (i, (count, position)) in sys.positions().into_iter().enumerate() {
        assert_eq!((count, position), (shafts[i], shafts[i]), "axis {i}");
    }
}

/// The steps an instant limit stop lets past the switch at VELOCITY with
/// a filter tick of `tick` clocks. From the shaft reaching the switch: 2
/// synchroniser edges, at most FILTER_TICKS ticks, LIMIT_LATENCY, 2 pin
/// registers and the drive's 3-clock pipeline; at most VELOCITY steps per
/// second meanwhile.
fn instant_overshoot(tick: u32) -> i32 {
    let latency = 2 + FILTER_TICKS * tick + LIMIT_LATENCY + 2 + 3;
    (f64::from(latency) * VELOCITY / f64::from(CLOCK_HZ)).ceil() as i32 + 1
}

#[test]
fn a_move_into_a_limit_stops_there_and_the_axis_can_back_off() {
    let (mut sys, tick) = two_axes_with_fast_filter();
    let switch = 500;
    sys.limit_pos_at[0] = Some(switch);
    // Axis 0's limits on, active high; LIMIT_CAUSE.POS of axis 0 on IRQ.
    sys.write("SAFETY", None, "LIMIT_POS_CTRL", 1);
    sys.write("SAFETY", None, "LIMIT_NEG_CTRL", 1);
    sys.write("SAFETY", None, "LIMIT_MASK", 1);
    sys.idle(u64::from(FILTER_TICKS * tick) + 10);
    assert_eq!(sys.read("SAFETY", None, "LIMIT_CAUSE"), 0);
    assert!(sys.irq(), "nothing yet: the active-low IRQ pin is high");

    let (far, other) = (plan(1000), plan(600));
    for s in &other.0 {
        sys.push(1, s);
    }
    run(&mut sys, 0, &far);
    let overshoot = instant_overshoot(tick);
    let stopped = shaft(&sys, 0);
    assert!(
        (switch..=switch + overshoot).contains(&stopped),
        "stopped at {stopped}, switch at {switch}, overshoot bound {overshoot}"
    );
    assert_eq!(
        shaft(&sys, 1),
        0,
        "axis 1 has not started (RUN was for axis 0)"
    );
    counts_are_exact(&mut sys);
    assert_eq!(sys.read("SAFETY", None, "LIMIT_CAUSE"), 1, "POS of axis 0");
    assert_eq!(
        sys.read("SAFETY", None, "LIMIT_INPUTS"),
        1,
        "the switch is closed"
    );
    assert!(!sys.irq(), "the unmasked limit cause pulls IRQ low");
    assert_eq!(sys.read("PULSE", None, "RUN") & 1, 0, "RUN cleared");

    // Axis 1 runs while axis 0 sits on its switch.
    sys.write("PULSE", None, "RUN", 2);
    sys.idle(other.1 + 2_000);
    assert_eq!(shaft(&sys, 1), 600);

    // Further into the switch: refused, not a step.
    run(&mut sys, 0, &plan(100));
    run(&mut sys, 0, &creep(100));
    assert_eq!(shaft(&sys, 0), stopped, "no step into the switch");
    assert_eq!(sys.read("PULSE", None, "RUN") & 1, 0);
    // A clear while the switch is still closed does not release it.
    sys.write("SAFETY", None, "LIMIT_CAUSE", 1);
    assert_eq!(sys.read("SAFETY", None, "LIMIT_CAUSE"), 1);

    // Away from it: runs in full.
    run(&mut sys, 0, &creep(-200));
    assert_eq!(shaft(&sys, 0), stopped - 200);
    counts_are_exact(&mut sys);
    assert_eq!(sys.read("SAFETY", None, "LIMIT_INPUTS"), 0, "switch open");
    sys.write("SAFETY", None, "LIMIT_CAUSE", 1);
    assert_eq!(sys.read("SAFETY", None, "LIMIT_CAUSE"), 0);
    assert!(sys.irq(), "cause cleared: IRQ released");
    run(&mut sys, 0, &creep(100));
    assert_eq!(
        shaft(&sys, 0),
        stopped - 100,
        "forward again after the clear"
    );
    counts_are_exact(&mut sys);
}

/// HOME_STOP (docs/safety_io.md, "Direction stops"): an axis heading for
/// its home switch stops on the switch's edge within the limit's latency,
/// moves neither way while HOME_ALARM_CAUSE.HOME is set, and runs on once
/// firmware clears it; without HOME_STOP the switch only sets the cause.
#[test]
fn home_stop_halts_the_axis_on_the_home_edge_until_the_cause_is_cleared() {
    let (mut sys, tick) = two_axes_with_fast_filter();
    let switch = 30;
    sys.home_at = vec![Some(switch), Some(switch)];
    sys.write("SAFETY", None, "HOME_CTRL", 3);
    sys.write("SAFETY", None, "HOME_STOP", 1);
    sys.idle(u64::from(FILTER_TICKS * tick) + 10);
    for axis in 0..2 {
        run(&mut sys, axis, &creep(60));
    }
    // One step per 100 clocks: the latency (well under 100 clocks) lets
    // at most one more step out after the shaft reaches the switch.
    let stopped = shaft(&sys, 0);
    assert!(
        (switch..=switch + 1).contains(&stopped),
        "axis 0 stopped at {stopped}"
    );
    assert_eq!(
        shaft(&sys, 1),
        60,
        "axis 1 has no HOME_STOP: it ran its move"
    );
    assert_eq!(
        sys.read("SAFETY", None, "HOME_ALARM_CAUSE"),
        3,
        "both saw HOME"
    );
    counts_are_exact(&mut sys);
    run(&mut sys, 0, &creep(-5));
    assert_eq!(
        shaft(&sys, 0),
        stopped,
        "no step either way while the cause is set"
    );
    sys.write("SAFETY", None, "HOME_ALARM_CAUSE", 1);
    run(&mut sys, 0, &creep(-5));
    assert_eq!(shaft(&sys, 0), stopped - 5, "after the clear it backs off");
    counts_are_exact(&mut sys);
}

/// A decelerating stop (AX.DECEL, docs/pulse_generator.md "Direction
/// stops"): the same kind of move into a switch brakes instead of stopping
/// at once. STATUS.BRAKING shows while it does, the shaft never steps back,
/// it comes to rest past the switch by at least most of v²/2a and at most
/// the instant stop's overshoot plus v²/2a, RUN and BRAKING are clear at
/// rest, and the switch then holds the axis as an instant stop does.
#[test]
fn a_move_into_a_limit_with_decel_brakes_to_rest_and_can_back_off() {
    let (mut sys, tick) = two_axes_with_fast_filter();
    let map = sys.map().clone();
    let status = map.block("PULSE").array("AX").register("STATUS");
    let switch = 1000;
    sys.limit_pos_at[0] = Some(switch);
    sys.write("SAFETY", None, "LIMIT_POS_CTRL", 1);
    // 4e9 steps/s² at CLOCK_HZ, in DECEL's 2^-48 steps/clock².
    let decel = (4e9 / f64::from(CLOCK_HZ).powi(2) * 2f64.powi(48)).round() as u32;
    sys.write("PULSE", Some(0), "DECEL", decel);
    assert_eq!(sys.read("PULSE", Some(0), "DECEL"), decel);
    sys.idle(u64::from(FILTER_TICKS * tick) + 10);

    let far = plan(4000);
    let top_rate = far.0.iter().map(|s| s.rate).max().unwrap();
    let expected = VELOCITY / f64::from(CLOCK_HZ) * 2f64.powi(32);
    assert!(
        (f64::from(top_rate) / expected - 1.0).abs() < 0.01,
        "cruise rate {top_rate}"
    );
    for s in &far.0 {
        sys.push(0, s);
    }
    sys.write("PULSE", None, "RUN", 1);
    let (mut peak, mut braked) = (0, 0);
    for _ in 0..(far.1 + 2_000) / 200 {
        sys.idle(200);
        let now = shaft(&sys, 0);
        assert!(now >= peak, "stepped back from {peak} to {now}");
        peak = now;
        let s = sys.read("PULSE", Some(0), "STATUS");
        braked += status.field("BRAKING").get(s);
    }
    assert!(braked > 10, "STATUS.BRAKING seen in {braked} polls");
    let v2_2a = brake_steps_bound(top_rate, decel) as i32;
    let instant = instant_overshoot(tick);
    let stopped = shaft(&sys, 0);
    assert!(
        (switch + v2_2a * 9 / 10..=switch + instant + v2_2a).contains(&stopped),
        "stopped at {stopped}: switch {switch}, v²/2a {v2_2a}, instant overshoot {instant}"
    );
    counts_are_exact(&mut sys);
    let s = sys.read("PULSE", Some(0), "STATUS");
    assert_eq!(status.field("BRAKING").get(s), 0, "at rest: STATUS {s:#x}");
    assert_eq!(sys.read("PULSE", None, "RUN") & 1, 0, "RUN cleared");
    assert_eq!(sys.read("SAFETY", None, "LIMIT_CAUSE"), 1, "POS of axis 0");

    // Past the switch it holds the axis as an instant stop does.
    run(&mut sys, 0, &creep(50));
    assert_eq!(shaft(&sys, 0), stopped, "no step further in");
    run(&mut sys, 0, &creep(-(stopped - switch + 50) as i64));
    assert_eq!(shaft(&sys, 0), switch - 50, "backed off past the switch");
    counts_are_exact(&mut sys);
    sys.write("SAFETY", None, "LIMIT_CAUSE", 1);
    assert_eq!(sys.read("SAFETY", None, "LIMIT_CAUSE"), 0);
}
