//! A limit switch in the whole controller (docs/safety_io.md, "Direction
//! stops"): the moves firmware uses around one, and `motionhdl trace
//! limit_stop` and `limit_brake`.

use super::system::{two_axes_on, Engine, System};
use crate::checks::pulse_bank::braking::brake_steps_bound;
use crate::trace::Trace;
use motionhdl_model::pulse_generator::Segment;
use motionhdl_model::Config;

/// A move of `steps` at one step per 100 clocks, as firmware backs off a
/// switch: one constant-rate segment, and its length in clocks. (An
/// S-curve's last segment can end with its rate just past zero when the
/// NCO's phase was not 0 at its start, as after a stop; with the switch's
/// stop still set that is a step toward the switch, and the axis stops.)
pub fn creep(steps: i64) -> (Vec<Segment>, u64) {
    creep_every(steps, 100)
}

/// A move of `steps` at one step per `period` clocks (as [`creep`]).
pub fn creep_every(steps: i64, period: i64) -> (Vec<Segment>, u64) {
    let rate = (1i64 << 32) / period * steps.signum();
    let segment = Segment {
        steps: steps.unsigned_abs() as u32,
        rate: rate as i32,
        accel: 0,
        jerk: 0,
    };
    (vec![segment], period.unsigned_abs() * steps.unsigned_abs())
}

/// Pushes a move to `axis`, sets RUN for it alone and idles the move's
/// length and a margin.
pub fn run<const N: usize>(
    sys: &mut System<N>,
    axis: u32,
    (segments, clocks): &(Vec<Segment>, u64),
) {
    for s in segments {
        sys.push(axis, s);
    }
    sys.write("PULSE", None, "RUN", 1 << axis);
    sys.idle(clocks + 2_000);
}

/// Two axes of `config`'s width and clock with a 1 µs input filter (so a
/// switch shows within a few steps), set up; and the filter's tick in
/// clocks; the top in `engine`.
pub fn fast_filter_axes(engine: Engine, config: &Config) -> (System<2>, u32) {
    let mut tick = 0;
    let sys = two_axes_on(engine, config, |c| {
        let c = c.with_input_filter_us(1).expect("1 us is allowed");
        tick = c.filter_tick_clocks();
        c
    });
    (sys, tick)
}

/// The traces' creep: one step per 100 clocks, or per two lengths of the
/// 1 µs input filter on a clock past 50 MHz, so the switch stops the axis
/// within a few steps at every clock.
fn trace_creep(config: &Config, steps: i64) -> (Vec<Segment>, u64) {
    let filter_clocks = i64::try_from(config.clock_hz() / 1_000_000).expect("clock fits");
    creep_every(steps, 100.max(2 * filter_clocks))
}

/// Where the trace's switch sits on axis 0's shaft.
pub const TRACE_SWITCH: i32 = 20;

/// `motionhdl trace limit_stop`: axis 0 creeps toward a LIMIT_POS switch
/// at shaft position 20 (two axes, the configuration's width and clock, a
/// 1 µs input filter so the stop shows within a few steps), stops on it
/// with LIMIT_CAUSE.POS and the IRQ pin low, a move further in is refused,
/// it backs off 10 steps, firmware clears the cause and IRQ rises again.
pub fn trace(config: &Config) -> Trace {
    let (mut sys, _) = fast_filter_axes(Engine::RustHdl, config);
    sys.limit_pos_at[0] = Some(TRACE_SWITCH);
    sys.write("SAFETY", None, "LIMIT_POS_CTRL", 1);
    sys.write("SAFETY", None, "LIMIT_MASK", 1);
    sys.idle(100);
    sys.record_scenario(config, "limit_stop");
    run(&mut sys, 0, &trace_creep(config, 40));
    let stopped = sys.drives[0].position;
    assert!(
        (TRACE_SWITCH..TRACE_SWITCH + 3).contains(&stopped),
        "limit trace: stopped at {stopped}"
    );
    assert!(!sys.irq(), "limit trace: IRQ low");
    run(&mut sys, 0, &creep(5));
    assert_eq!(sys.drives[0].position, stopped, "limit trace: refused");
    run(&mut sys, 0, &creep(-10));
    sys.mark("LIMIT_CAUSE cleared");
    sys.write("SAFETY", None, "LIMIT_CAUSE", 1);
    sys.idle(200);
    sys.mark_edge("axis0.limit_pos", 1, 0, "limit switch hit");
    assert!(sys.irq(), "limit trace: cause cleared, IRQ released");
    let p = sys.positions();
    let back = stopped - 10;
    assert_eq!(p[0], (back, back), "limit trace: counted back");
    sys.take_trace().expect("recording")
}

/// AX.DECEL of axis 0 in `motionhdl trace limit_brake`, 2^-48 steps per
/// clock²: from the creep's rate the brake takes about 26 steps.
pub const TRACE_DECEL: u32 = 1 << 29;

/// `motionhdl trace limit_brake`: as `limit_stop`, but axis 0 has DECEL
/// set, so the limit brakes it: the step spacing widens past the switch
/// until the axis comes to rest about v²/2a beyond it (IRQ low from the
/// switch's edge); a move further in is refused, it backs off to 10 steps
/// short of the switch, firmware clears the cause and IRQ rises again.
pub fn brake_trace(config: &Config) -> Trace {
    let (mut sys, _) = fast_filter_axes(Engine::RustHdl, config);
    sys.limit_pos_at[0] = Some(TRACE_SWITCH);
    sys.write("SAFETY", None, "LIMIT_POS_CTRL", 1);
    sys.write("SAFETY", None, "LIMIT_MASK", 1);
    sys.write("PULSE", Some(0), "DECEL", TRACE_DECEL);
    sys.idle(100);
    sys.record_scenario(config, "limit_brake");
    let approach = creep(100);
    run(&mut sys, 0, &approach);
    let stopped = sys.drives[0].position;
    let v2_2a = brake_steps_bound(approach.0[0].rate, TRACE_DECEL) as i32;
    assert!(
        (TRACE_SWITCH + v2_2a * 3 / 4..=TRACE_SWITCH + v2_2a + 2).contains(&stopped),
        "brake trace: stopped at {stopped}, v²/2a {v2_2a}"
    );
    assert!(!sys.irq(), "brake trace: IRQ low");
    run(&mut sys, 0, &creep(5));
    assert_eq!(sys.drives[0].position, stopped, "brake trace: refused");
    let back = TRACE_SWITCH - 10;
    run(&mut sys, 0, &creep(i64::from(back - stopped)));
    sys.mark("LIMIT_CAUSE cleared");
    sys.write("SAFETY", None, "LIMIT_CAUSE", 1);
    sys.idle(200);
    sys.mark_edge("axis0.limit_pos", 1, 0, "limit switch hit");
    assert!(sys.irq(), "brake trace: cause cleared, IRQ released");
    assert_eq!(
        sys.positions()[0],
        (back, back),
        "brake trace: counted back"
    );
    sys.take_trace().expect("recording")
}
