//! Pulse generator: the step timer exhaustively, the axis against the model
//! every clock in rust-hdl, Icarus and Verilator, and the contract of the
//! waveform (timings honoured, emitted = commanded, within one step of the
//! ideal NCO) for random parameters.

use motionhdl_firmware::segments::segment_clocks;
use motionhdl_model::pulse_generator::{Segment, StepTiming};
use motionhdl_testbench::checks::pulse_bank as pb;
use motionhdl_testbench::checks::pulse_bank::braking;
use motionhdl_testbench::checks::pulse_generator as pg;
use motionhdl_testbench::scale;
use motionhdl_testbench::verilog_sim::Simulator;
use proptest::prelude::*;

#[test]
fn step_timer_every_reachable_state_and_input() {
    let (r, pairs) = pg::exhaustive_timer();
    // 3 requests x 3^4 timings x flush or not = 486 inputs in every
    // reachable state.
    assert_eq!(pg::narrow_inputs().len(), 486);
    // 992 reachable states: queue -3..=3, S1, S2, the two timers (their
    // next clock's value, 2..=7), the four timing flags (which a timing
    // change leaves true or false at the same timer value) and the step
    // leaving the queue (a flush reaches no state the others do not).
    // Counted by the model's breadth-first search.
    assert_eq!(pairs, 992 * 486);
    r.assert_passed();
    assert_eq!(r.covered, pairs, "pairs covered = pairs enumerated");
}

#[test]
fn axis_against_model_every_clock_rust_hdl() {
    let r = pg::random_rust(200_000, 0x5eed_0001);
    r.assert_passed();
    assert_eq!(r.covered, 200_000);
}

#[test]
fn axis_against_model_generated_verilog() {
    let r = pg::random_verilog(Simulator::Icarus, 100_000, 0x5eed_0002);
    r.assert_passed();
    if r.skipped.is_none() {
        assert_eq!(r.covered, 100_000);
    }
    let r = pg::random_verilog(Simulator::Verilator, 2_000_000, 0x5eed_0003);
    r.assert_passed();
    if r.skipped.is_none() {
        assert_eq!(r.covered, 2_000_000);
    }
}

#[test]
fn pulse_bank_registers_and_outputs_against_model() {
    let r = pb::bank_rust(100_000, 0x5eed_0004);
    r.assert_passed();
    assert_eq!(r.covered, 100_000);
}

#[test]
fn loopback_into_the_counter_bank_counts_every_step() {
    // The dual-CPU seed's loop: pulse generator -> selector -> counter bank,
    // in pulse+direction, CW/CCW and quadrature (counted x4), several random
    // schedules each.
    let mut total = 0;
    for output in pb::Output::ALL {
        for seed in 1..=4u64 {
            let (position, counted, clocks) = pb::loopback(output, seed * 0x9e37_79b9, 12);
            assert_eq!(counted, position, "{output:?} seed {seed}: {clocks} clocks");
            total += position.unsigned_abs();
        }
    }
    // The schedules move: a loop that never steps would pass trivially.
    assert!(total > 1000, "only {total} steps in all loops");
}

#[test]
fn a_move_through_the_segment_fifo_ends_on_the_commanded_steps() {
    // An S-curve-like stream in 7 segments (more than the FIFO holds):
    // accelerate, cruise, decelerate, then the same backwards, plus a
    // zero-length segment.
    let k = 1 << 20;
    let segments = [
        Segment {
            steps: 40,
            rate: k,
            accel: 64 << 16,
            jerk: 0,
        },
        Segment {
            steps: 120,
            rate: 40 * k,
            accel: 0,
            jerk: 0,
        },
        Segment {
            steps: 40,
            rate: 40 * k,
            accel: -64 << 16,
            jerk: 0,
        },
        Segment {
            steps: 0,
            rate: k,
            accel: 0,
            jerk: 0,
        },
        Segment {
            steps: 30,
            rate: -k,
            accel: -64 << 16,
            jerk: 0,
        },
        Segment {
            steps: 50,
            rate: -30 * k,
            accel: 0,
            jerk: 0,
        },
        Segment {
            steps: 30,
            rate: -30 * k,
            accel: 64 << 16,
            jerk: 0,
        },
    ];
    let timing = StepTiming {
        step_len: 3,
        step_space: 2,
        dir_setup: 4,
        dir_hold: 2,
    };
    let (r, position, expected) = pb::move_rust(&segments, timing);
    r.assert_passed();
    assert!(r.covered > 10_000, "{} clocks", r.covered);
    assert_eq!(expected, 200 - 110);
    assert_eq!(position, expected);
}

proptest! {
    // Knob `ramped_move_cases`: 12 moves at the default scale, 48 long.
    #![proptest_config(ProptestConfig::with_cases(
        u32::try_from(scale::cases("ramped_move_cases")).unwrap()
    ))]

    /// Random segment streams with ramps: start rate, acceleration with its
    /// fraction bits, jerk, and reversals between segments. The move ends
    /// exactly on the sum of the segments' steps (no step lost), and the
    /// HDL's rate, acceleration and jerk equal the model's every clock.
    #[test]
    fn random_ramped_moves_end_exactly(
        t in timing(),
        segs in prop::collection::vec(ramped_segment(), 1..7),
    ) {
        let (r, position, expected) = pb::move_rust(&segs, t);
        prop_assert!(r.failures.is_empty(), "{:?}", r.failures);
        prop_assert_eq!(position, expected);
    }
}

/// The strategy keeps most ramps: a fallback to a constant rate would make
/// the property above test little.
#[test]
fn ramped_segments_mostly_carry_a_ramp() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = ramped_segment();
    let (mut jerk, mut fraction, n) = (0, 0, 400);
    for _ in 0..n {
        let s = strategy.new_tree(&mut runner).unwrap().current();
        jerk += usize::from(s.jerk != 0);
        fraction += usize::from(s.accel != 0 && s.accel.unsigned_abs() < 1 << 16);
    }
    assert!(jerk >= n / 3, "{jerk} of {n} segments with a jerk");
    assert!(
        fraction >= n / 10,
        "{fraction} of {n} with a fraction-only accel"
    );
}

/// A segment whose rate keeps its sign until its last step and which takes
/// at most 20 000 clocks (from phase 0, the slowest start); else the same
/// steps at a constant rate. Accel and jerk are often small (fraction-only
/// ramps) and sometimes steep.
fn ramped_segment() -> impl Strategy<Value = Segment> {
    let accel = prop_oneof![-(1i32 << 16)..(1 << 16), -(1i32 << 27)..(1 << 27)];
    let jerk = prop_oneof![
        Just(0i32),
        -(1i32 << 16)..(1 << 16),
        -(1i32 << 30)..(1 << 30)
    ];
    (
        0u32..200,
        (1i32 << 22)..(1 << 27),
        accel,
        jerk,
        any::<bool>(),
    )
        .prop_map(|(steps, rate, accel, jerk, negative)| {
            let sign = if negative { -1 } else { 1 };
            let seg = Segment {
                steps,
                rate: sign * rate,
                accel: sign * accel,
                jerk: sign * jerk,
            };
            match segment_clocks(&seg, 0) {
                Some(run) if run.clocks <= 20_000 => seg,
                _ => Segment {
                    accel: 0,
                    jerk: 0,
                    rate: sign * (1 << 26),
                    ..seg
                },
            }
        })
}

#[test]
fn a_timing_violation_is_caught() {
    // The contract checker itself must fail on a bad waveform: a one-clock
    // pulse against step_len 2, and S2 changing while S1 is high.
    let t = StepTiming {
        step_len: 2,
        ..Default::default()
    };
    let out = [(false, false, 0), (true, false, 1), (false, false, 1)];
    assert_eq!(pg::timing_violations(&t, &out).len(), 1);
    let out = [
        (false, false, 0),
        (true, false, 1),
        (true, true, 1),
        (false, true, 1),
    ];
    assert!(!pg::timing_violations(&StepTiming::default(), &out).is_empty());
}

fn timing() -> impl Strategy<Value = StepTiming> {
    (0u32..8, 0u32..8, 0u32..8, 0u32..8).prop_map(|(l, s, su, h)| StepTiming {
        step_len: l,
        step_space: s,
        dir_setup: su,
        dir_hold: h,
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random rates and reversals: every timing honoured, no runt, and once
    /// the queue drains the position equals the commanded steps.
    #[test]
    fn emitted_equals_commanded_and_timing_holds(
        t in timing(),
        schedule in prop::collection::vec(
            (prop_oneof![Just(i32::MIN), Just(i32::MAX), any::<i32>(), (-1i32 << 28)..(1 << 28)], 1usize..600),
            1..8,
        ),
    ) {
        let (commanded, out) = pg::run_schedule(t, &schedule);
        let v = pg::timing_violations(&t, &out);
        prop_assert!(v.is_empty(), "{:?}", &v[..v.len().min(5)]);
        let position = out.last().unwrap().2 as i32 as i64;
        prop_assert_eq!(position, commanded);
    }

    /// A rate the timing can follow: over any window the emitted count is
    /// within one step of the ideal NCO (floor(k × rate / 2^32)), apart
    /// from the pipeline's fixed two-clock lag.
    #[test]
    fn within_one_step_of_the_ideal_nco(
        t in timing(),
        rate in 1u32..(1 << 28),
        negative in any::<bool>(),
        clocks in 100usize..5000,
    ) {
        let period = u64::from(t.step_len.max(1) + t.step_space.max(1));
        // Fast enough rates are throttled by the timing: skip those.
        prop_assume!(u64::from(rate) * period < (1u64 << 32));
        let signed = if negative { -(rate as i32) } else { rate as i32 };
        let (_, out) = pg::run_schedule(t, &[(signed, clocks)]);
        // Direction set-up delays the first negative step once.
        let lag = 2 + if negative { t.dir_hold.max(1) as usize + t.dir_setup.max(1) as usize } else { 0 };
        for k in 0..clocks {
            let ideal = ((k + 1) as u64 * u64::from(rate)) >> 32;
            let got = (out[(k + lag).min(out.len() - 1)].2 as i32).unsigned_abs() as u64;
            prop_assert!(got.abs_diff(ideal) <= 1, "clock {}: {} steps, ideal {}", k, got, ideal);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// CW/CCW through the registered selector: F1 and F2 are never high
    /// together and every pulse on either lasts at least STEP_LEN clocks,
    /// across reversals (no runt at a direction change).
    #[test]
    fn no_runt_on_f1_f2_in_cw_ccw(
        t in timing(),
        rates in prop::collection::vec(any::<i32>(), 1..8),
    ) {
        use motionhdl_model::counter::BusCycle;
        use motionhdl_model::pulse_generator::PulseBank;
        use motionhdl_model::regmap;
        let map = regmap::pulse_bank(1, 28);
        let ax = map.array("AX");
        let mut bank = PulseBank::new(1, 28);
        let mut out = Vec::new();
        let clock = |bank: &mut PulseBank, bus: BusCycle, out: &mut Vec<(bool, bool)>| {
            bank.clock(false, &bus, false);
            out.push(bank.outputs(0));
        };
        clock(&mut bank, BusCycle::write(ax.address(0, "CTRL"), 1), &mut out);
        clock(&mut bank, BusCycle::write(ax.address(0, "STEP_TIMING"), t.step_len | t.step_space << 16), &mut out);
        clock(&mut bank, BusCycle::write(ax.address(0, "DIR_TIMING"), t.dir_setup | t.dir_hold << 16), &mut out);
        clock(&mut bank, BusCycle::write(map.register("RUN").offset, 1), &mut out);
        for rate in rates {
            clock(&mut bank, BusCycle::write(ax.address(0, "RATE"), (rate >> 2) as u32), &mut out);
            for _ in 0..300 {
                clock(&mut bank, BusCycle::default(), &mut out);
            }
        }
        for line in 0..2 {
            let level: Vec<bool> = out.iter().map(|o| if line == 0 { o.0 } else { o.1 }).collect();
            let mut k = 0;
            while k < level.len() {
                let mut j = k;
                while j < level.len() && level[j] == level[k] {
                    j += 1;
                }
                if level[k] && j < level.len() {
                    prop_assert!(j - k >= t.step_len.max(1) as usize, "F{} pulse of {} clocks", line + 1, j - k);
                }
                k = j;
            }
        }
        prop_assert!(out.iter().all(|o| !(o.0 && o.1)), "F1 and F2 high together");
    }
}

/// docs/pulse_generator.md, "Direction stops": a decelerating stop
/// commands at most RATE²/(2^17·DECEL) + 2 more steps, all the way it was
/// heading; the same bound with DECEL taken 4 times as large fails.
#[test]
fn a_decelerating_stop_commands_at_most_v_squared_over_2a() {
    let (r, worst) = braking::braking_contract(1_000_000, 0x5eed_0b4a, 1);
    eprintln!(
        "{}: {} brakes, the longest used {worst} % of its bound",
        r.result(),
        r.covered
    );
    r.assert_passed();
    assert!(r.covered >= 100, "only {} brakes ended", r.covered);
    assert!(worst >= 50, "no brake came near its bound ({worst} %)");
    let (broken, _) = braking::braking_contract(1_000_000, 0x5eed_0b4a, 4);
    assert!(
        !broken.failures.is_empty(),
        "a bound 4 times too tight caught {} brakes",
        broken.failures.len()
    );
}
