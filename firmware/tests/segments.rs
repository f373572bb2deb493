//! Profiles as pulse-generator segments: exact step counts, rates within the
//! NCO's range, and the clock estimate against the move engine model.

use motionhdl_firmware::scurve::{SCurve, SCurveParams};
use motionhdl_firmware::segments::{
    direction, floor_sum, segment_clocks, segments, SegmentBuilder, SegmentConfig, SegmentError,
    SegmentRun, CLOCK_LIMIT, RATE_MAX,
};
use motionhdl_firmware::trapezoid::{TrapezoidParams, TrapezoidStepper};
use motionhdl_firmware::ONE;
use motionhdl_model::pulse_generator::{
    MoveEngine, PulseGenerator, PulseInputs, Request, Segment, StepTiming, SEGMENT_FIFO_DEPTH,
};
use proptest::prelude::*;

/// The NCO clock by clock, as docs/pulse_generator.md describes the move
/// engine: a u64 phase accumulator; |rate| added per clock, a step per
/// carry; the rate and the acceleration carry 16 fraction bits, the rate
/// grows by the acceleration's whole part and the acceleration by the jerk.
/// `None` if the rate changes sign or leaves i32 before the last step or
/// `limit` clocks pass.
fn nco_reference(seg: &Segment, mut phase: u64, limit: u64) -> Option<SegmentRun> {
    if seg.steps == 0 {
        return Some(SegmentRun {
            clocks: 1,
            phase: phase as u32,
        });
    }
    let dir = direction(seg);
    let (mut rate, mut accel) = (
        (i64::from(seg.rate) << 16) + (1 << 15),
        (i64::from(seg.accel) << 16) + (1 << 15),
    );
    let mut steps = 0;
    for clock in 1..=limit {
        let nco = rate.div_euclid(1 << 16);
        if nco * dir < 0 || i32::try_from(nco).is_err() {
            return None;
        }
        phase += nco.unsigned_abs();
        if phase >> 32 != 0 {
            phase &= 0xFFFF_FFFF;
            steps += 1;
            if steps == seg.steps {
                return Some(SegmentRun {
                    clocks: clock + 1,
                    phase: phase as u32,
                });
            }
        }
        rate += accel.div_euclid(1 << 16);
        accel += i64::from(seg.jerk);
    }
    None
}

#[test]
fn hand_computed_segment_clocks() {
    // One step at the top rate 2^31 − 1 from phase 0: 2 clocks give
    // 2^32 − 2, 3 give 2^32 + 2^31 − 3: the step is on the third, plus the
    // load clock; the phase left is 2^31 − 3.
    let s = Segment {
        steps: 1,
        rate: i32::MAX,
        ..Default::default()
    };
    assert_eq!(
        segment_clocks(&s, 0),
        Some(SegmentRun {
            clocks: 4,
            phase: (1 << 31) - 3
        })
    );
    // From rest at accel 2^30 (2^14 rate LSBs a clock): S(n) =
    // 2^14·n(n−1)/2 >= 2^32 needs n(n−1) >= 2^19 = 524 288: n = 725
    // (725·724 = 524 900; 724·723 = 523 452). Phase left: 2^13·524 900 −
    // 2^32 = 2^13·612.
    let s = Segment {
        steps: 1,
        accel: 1 << 30,
        ..Default::default()
    };
    assert_eq!(
        segment_clocks(&s, 0),
        Some(SegmentRun {
            clocks: 726,
            phase: 612 << 13
        })
    );
    // Backwards, the same.
    let s = Segment {
        steps: 1,
        accel: -(1 << 30),
        ..Default::default()
    };
    assert_eq!(segment_clocks(&s, 0).unwrap().clocks, 726);
    // A fraction-only ramp: accel 3 (3·2^-16 rate LSBs a clock) from rate
    // 2^31 − 3 reaches 2^31 − 1 (the top) after ⌈2^17/3⌉ = 43 691 clocks,
    // where the floor sum must agree with the clock-by-clock reference.
    let s = Segment {
        steps: 30_000,
        rate: i32::MAX - 2,
        accel: 3,
        jerk: 0,
    };
    assert_eq!(segment_clocks(&s, 5), nco_reference(&s, 5, 100_000));
    // Past the top rate it never completes.
    let s = Segment { steps: 40_000, ..s };
    assert_eq!(segment_clocks(&s, 5), None);
    // Decelerating through zero before the step: never completes.
    let s = Segment {
        steps: 3,
        rate: 1 << 20,
        accel: -(1 << 26),
        jerk: 0,
    };
    assert_eq!(segment_clocks(&s, 0), None);
    // The same with a jerk that turns the rate back up in time: the
    // rate's minimum is 2^20 − 2^10·k + 2^-16·j·k²/2 ...; the clock-by-
    // clock follower agrees with the reference.
    let s = Segment { jerk: 1 << 20, ..s };
    assert_eq!(segment_clocks(&s, 0), nco_reference(&s, 0, 1 << 20));
    // A zero-step segment is consumed on its load clock.
    let s = Segment {
        steps: 0,
        rate: 5,
        ..Default::default()
    };
    assert_eq!(
        segment_clocks(&s, 77),
        Some(SegmentRun {
            clocks: 1,
            phase: 77
        })
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn floor_sum_is_the_sum_of_floors(
        n in 0i128..300, m in 1i128..5000, a in -100_000i128..100_000, b in -1_000_000i128..1_000_000,
    ) {
        let want: i128 = (0..n).map(|i| (a * i + b).div_euclid(m)).sum();
        prop_assert_eq!(floor_sum(n, m, a, b), want);
    }

    #[test]
    fn segment_clocks_is_the_clock_by_clock_nco(
        steps in 0u32..40, rate in any::<i32>(), accel_shift in 0u32..31, accel_sign in any::<bool>(),
        jerk in prop_oneof![Just(0i32), -(1i32 << 12)..(1 << 12), -(1i32 << 30)..(1 << 30)],
        phase in any::<u32>(),
    ) {
        // Rates large enough to finish within the reference's clock budget:
        // pushed 2^24 away from zero, but for those within 2^24 of the i32
        // range's ends, which are large already (a push would overflow).
        let base = rate / 64 * 64;
        let rate = base.checked_add(if rate < 0 { -(1 << 24) } else { 1 << 24 }).unwrap_or(base);
        let accel = (1i32 << accel_shift) * if accel_sign { -1 } else { 1 };
        let seg = Segment { steps, rate, accel, jerk };
        let limit = 200_000;
        let want = nco_reference(&seg, u64::from(phase), limit);
        let got = segment_clocks(&seg, phase);
        match (want, got) {
            (Some(w), Some(g)) => prop_assert_eq!(w, g),
            (None, None) => {}
            // The reference gave up at its limit: the estimate must be longer.
            (None, Some(g)) => prop_assert!(g.clocks > limit, "{:?}", g),
            (Some(w), None) => prop_assert!(false, "reference completes: {:?}", w),
        }
    }
}

/// Runs `segs` through the model's move engine and pulse generator, wired as
/// in the pulse bank, topping the FIFO up as it drains. Returns (clocks from
/// the first segment's load to the clock the last step is commanded,
/// position once the step queue has drained).
fn run_move_engine(segs: &[Segment]) -> (u64, i64) {
    let timing = StepTiming {
        step_len: 1,
        step_space: 1,
        dir_setup: 1,
        dir_hold: 1,
    };
    let (mut eng, mut gen) = (MoveEngine::default(), PulseGenerator::new());
    let (mut pushed, mut clock, mut first_load) = (0, 0u64, None);
    loop {
        let inputs = PulseInputs {
            enable: true,
            halt: false,
            rate: eng.rate(),
            timing,
        };
        let (request, blocked) = gen.request(&inputs);
        let push = (pushed < segs.len() && eng.level() < SEGMENT_FIFO_DEPTH).then(|| {
            pushed += 1;
            segs[pushed - 1]
        });
        let was_active = eng.active();
        eng.clock(true, request != Request::None, !blocked, push);
        gen.clock(&inputs, false);
        if first_load.is_none() && !was_active && eng.active() {
            first_load = Some(clock);
        }
        clock += 1;
        if pushed == segs.len() && eng.level() == 0 && !eng.active() && clock > 1 {
            break;
        }
        assert!(clock < 1 << 26, "the move does not end");
    }
    let end = clock;
    // Let the queued steps out.
    while gen.busy() {
        gen.clock(
            &PulseInputs {
                enable: true,
                halt: false,
                rate: 0,
                timing,
            },
            false,
        );
    }
    (
        end - first_load.unwrap_or(0),
        i64::from(gen.position as i32),
    )
}

/// Random S-curves within a clock of 200 kHz and a 1 kHz tick (C = 200, so
/// the model runs quickly): V up to 80 steps/tick, under the NCO's 100.
fn small_scurve() -> impl Strategy<Value = SCurveParams> {
    (1i64 << 24..1 << 30, 3i64..40, 3i64..40, -4000i64..=4000).prop_map(|(jerk, ka, kv, d)| {
        let accel = jerk * ka;
        let velocity = (accel * kv).min(80 * ONE);
        SCurveParams {
            jerk,
            accel,
            velocity,
            distance: d,
        }
    })
}

fn check_segments(segs: &[Segment], target: i64) -> Result<(), TestCaseError> {
    let total: i64 = segs.iter().map(|s| direction(s) * i64::from(s.steps)).sum();
    prop_assert_eq!(total, target);
    let mut phase = 0;
    for s in segs {
        prop_assert!(s.steps > 0);
        prop_assert!(i64::from(s.rate).abs() <= RATE_MAX);
        // Over the clocks it runs, the rate keeps its sign and its range.
        let run = segment_clocks(s, phase);
        prop_assert!(run.is_some(), "{:?} never completes", s);
        let run = run.unwrap();
        prop_assert_eq!(s.jerk, 0);
        let end_rate =
            ((i64::from(s.rate) << 16) + (1 << 15) + i64::from(s.accel) * (run.clocks as i64 - 2))
                >> 16;
        prop_assert!(
            end_rate.abs() <= 1 << 31,
            "{:?} ends at rate {}",
            s,
            end_rate
        );
        prop_assert!(
            end_rate * direction(s) >= 0,
            "{:?} turns to {}",
            s,
            end_rate
        );
        phase = run.phase;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn scurve_segments_drive_the_model_to_the_target(p in small_scurve()) {
        let cfg = SegmentConfig { clock_hz: 200_000, tick_hz: 1000, phase: 0 };
        let c = SCurve::new(p).unwrap();
        let mut b = SegmentBuilder::new(cfg, 32, 0).unwrap();
        let mut segs = Vec::new();
        for s in c.samples().skip(1) {
            segs.extend(b.push(s.position).unwrap());
        }
        segs.extend(b.finish().unwrap());
        check_segments(&segs, p.distance)?;
        let (clocks, position) = run_move_engine(&segs);
        prop_assert_eq!(position, p.distance);
        // The estimate is the model's clock count, exactly.
        prop_assert_eq!(clocks, b.clocks());
        // And near the profile's duration: segments end when their last
        // step is out, which is early or late by a part of a tick, most on
        // slow ticks where a step spans several ticks. A rate in the wrong
        // unit would be off by a factor of 2 or more.
        let nominal = c.ticks() * cfg.clocks_per_tick();
        let ratio = clocks as f64 / nominal as f64;
        if p.distance.abs() >= 100 {
            prop_assert!((0.75..1.25).contains(&ratio), "{} clocks vs {} nominal", clocks, nominal);
        }
    }

    #[test]
    fn trapezoid_segments_at_50_mhz_sum_to_the_target(
        steps in 0u32..50_000, vt in 1000u32..200_000, ka in 1u32..20, start_pct in 0u32..50,
    ) {
        let p = TrapezoidParams {
            start_speed: vt / 100 * start_pct,
            accel: vt * ka,
            target_speed: vt,
            decel: vt * ka,
            steps,
        };
        let pos: Vec<i64> = TrapezoidStepper::new(&p, 1000).unwrap().map(|s| s.position).collect();
        let cfg = SegmentConfig::default();
        let segs = segments(&pos, 32, cfg).unwrap();
        check_segments(&segs, i64::from(steps))?;
        // Whole-step positions give the same total.
        let whole: Vec<i64> = pos.iter().map(|q| q >> 32).collect();
        let segs = segments(&whole, 0, cfg).unwrap();
        check_segments(&segs, i64::from(steps))?;
    }
}

#[test]
fn a_reversal_steps_both_ways() {
    // Whole-step positions out to +5 and back to −2, at 1 kHz and 50 MHz.
    let pos = [0, 1, 3, 5, 5, 4, 2, 0, -2, -2];
    let segs = segments(&pos, 0, SegmentConfig::default()).unwrap();
    let signed: Vec<i64> = segs
        .iter()
        .map(|s| direction(s) * i64::from(s.steps))
        .collect();
    assert_eq!(signed, [1, 2, 2, -1, -2, -2, -2]);
    assert_eq!(signed.iter().sum::<i64>(), -2);
    let (clocks, position) = run_move_engine(
        &segments(
            &pos,
            0,
            SegmentConfig {
                clock_hz: 20_000,
                tick_hz: 1000,
                phase: 0,
            },
        )
        .unwrap(),
    );
    assert_eq!(position, -2);
    assert!(clocks > 0);
}

#[test]
fn too_fast_and_bad_configs_are_refused() {
    // 150 steps in a 100-clock tick: more than the NCO's one per two clocks.
    let cfg = SegmentConfig {
        clock_hz: 100_000,
        tick_hz: 1000,
        phase: 0,
    };
    match segments(&[0, 150, 300, 300], 0, cfg) {
        Err(SegmentError::TooFast { tick, rate, max }) => {
            assert_eq!(max, RATE_MAX);
            assert!(rate > RATE_MAX);
            assert_eq!(tick, 0);
        }
        other => panic!("{other:?}"),
    }
    let bad = SegmentConfig {
        tick_hz: 30_000,
        ..cfg
    };
    match segments(&[0, 1], 0, bad) {
        Err(SegmentError::Config(e)) => {
            assert_eq!(
                (e.name, e.value, e.min, e.max),
                ("tick_hz", 30_000, 1, 25_000)
            );
        }
        other => panic!("{other:?}"),
    }
    match SegmentBuilder::new(cfg, 33, 0) {
        Err(SegmentError::Config(e)) => assert_eq!((e.name, e.value), ("frac_bits", 33)),
        other => panic!("{other:?}"),
    }
    assert_eq!(segments(&[], 0, cfg).unwrap(), []);
    // A rate of 1 takes 2^32 clocks a step: 2^16 steps take exactly the
    // limit's 2^48 advancing clocks (plus the load clock), one more step is
    // past it.
    let slow = |steps| Segment {
        steps,
        rate: 1,
        ..Default::default()
    };
    assert_eq!(CLOCK_LIMIT, 1 << 48);
    assert_eq!(
        segment_clocks(&slow(1 << 16), 0).map(|r| r.clocks),
        Some((1 << 48) + 1)
    );
    assert_eq!(segment_clocks(&slow((1 << 16) + 1), 0), None);
}
