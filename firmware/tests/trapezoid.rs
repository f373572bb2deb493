//! Trapezoidal moves (seed 000): the master's phase point counts and the
//! per-tick stepper.

use motionhdl_firmware::trapezoid::{
    plan, TickLimits, TrapezoidParams, TrapezoidPhase, TrapezoidPlan, TrapezoidSample,
    TrapezoidStepper, MAX_ACCEL, MAX_SPEED, MAX_STEPS,
};
use motionhdl_firmware::{whole_steps, OutOfRange, ONE};
use proptest::prelude::*;

fn params(v0: u32, a: u32, vt: u32, d: u32, n: u32) -> TrapezoidParams {
    TrapezoidParams {
        start_speed: v0,
        accel: a,
        target_speed: vt,
        decel: d,
        steps: n,
    }
}

#[test]
fn plan_of_a_move_that_cruises() {
    // v0 = 1000, vt = 5000 steps/s: vt² − v0² = 25e6 − 1e6 = 24e6.
    // Accel at 10000 steps/s²: 24e6 / 20000 = 1200 points.
    // Decel at 5000 steps/s²: 24e6 / 10000 = 2400 points.
    // Cruise: 10000 − 1200 − 2400 = 6400 points.
    let p = plan(&params(1000, 10_000, 5000, 5000, 10_000)).unwrap();
    assert_eq!(
        p,
        TrapezoidPlan {
            accel_steps: 1200,
            cruise_steps: 6400,
            decel_steps: 2400,
            peak_speed: 5000,
            triangular: false,
        }
    );
}

#[test]
fn plan_of_a_move_too_short_to_cruise() {
    // The same ramps need 1200 + 2400 = 3600 > 2000 points: triangular.
    // Meeting point: n_acc = 2000·5000/(10000 + 5000) = 666.7 → 666,
    // n_dec = 2000 − 666 = 1334, peak = √(1000² + 2·10000·666)
    // = √14 320 000 = 3784.2 → 3784.
    let p = plan(&params(1000, 10_000, 5000, 5000, 2000)).unwrap();
    assert_eq!(
        p,
        TrapezoidPlan {
            accel_steps: 666,
            cruise_steps: 0,
            decel_steps: 1334,
            peak_speed: 3784,
            triangular: true,
        }
    );
}

#[test]
fn plan_at_the_start_speed_is_all_cruise() {
    let p = plan(&params(3000, 1, 3000, 1, 777)).unwrap();
    assert_eq!((p.accel_steps, p.cruise_steps, p.decel_steps), (0, 777, 0));
    assert!(!p.triangular);
}

#[test]
fn bad_parameters_are_named_with_their_range() {
    let good = params(100, 1000, 2000, 1000, 500);
    let cases = [
        (
            TrapezoidParams {
                target_speed: 0,
                ..good
            },
            ("target_speed", 0, 1, i64::from(MAX_SPEED)),
        ),
        (
            TrapezoidParams {
                target_speed: MAX_SPEED + 1,
                ..good
            },
            (
                "target_speed",
                i64::from(MAX_SPEED) + 1,
                1,
                i64::from(MAX_SPEED),
            ),
        ),
        (
            TrapezoidParams {
                start_speed: 2001,
                ..good
            },
            ("start_speed", 2001, 0, 2000),
        ),
        (
            TrapezoidParams { accel: 0, ..good },
            ("accel", 0, 1, i64::from(MAX_ACCEL)),
        ),
        (
            TrapezoidParams { decel: 0, ..good },
            ("decel", 0, 1, i64::from(MAX_ACCEL)),
        ),
        (
            TrapezoidParams {
                steps: MAX_STEPS + 1,
                ..good
            },
            ("steps", i64::from(MAX_STEPS) + 1, 0, i64::from(MAX_STEPS)),
        ),
    ];
    for (p, (name, value, min, max)) in cases {
        let e = plan(&p).unwrap_err();
        assert_eq!(
            e,
            OutOfRange {
                name,
                value,
                min,
                max
            }
        );
        assert_eq!(
            e.to_string(),
            format!("{name} = {value} out of range {min}..={max}")
        );
        assert_eq!(TrapezoidStepper::new(&p, 1000).unwrap_err(), e);
    }
    let e = TrapezoidStepper::new(&good, 0).unwrap_err();
    assert_eq!((e.name, e.value), ("tick_hz", 0));
}

#[test]
fn stepper_converts_units_per_tick() {
    // 1000 steps/s at 1 kHz is one step per tick; 2e6 steps/s² is 2 steps
    // per tick per tick.
    let s = TrapezoidStepper::new(&params(1000, 2_000_000, 4000, 1_000_000, 10), 1000).unwrap();
    let l = s.limits();
    assert_eq!(
        (l.start, l.accel, l.max, l.decel),
        (ONE, 2 * ONE, 4 * ONE, ONE)
    );
}

/// A valid move of at most about 10^4 ticks.
fn small_move() -> impl Strategy<Value = (TrapezoidParams, u32)> {
    (
        200u32..4000,
        100u32..100_000,
        0u32..=100,
        1u64..100,
        1u64..100,
        any::<u32>(),
    )
        .prop_map(|(tick, vt, start_pct, ka, kd, n)| {
            let p = TrapezoidParams {
                start_speed: (u64::from(vt) * u64::from(start_pct) / 100) as u32,
                // Ramps of 1/50 s to 2 s.
                accel: (u64::from(vt) * ka / 2) as u32,
                target_speed: vt,
                decel: (u64::from(vt) * kd / 2) as u32,
                // At most 2 s of cruise.
                steps: n % (2 * vt.min(10_000) + 1),
            };
            (p, tick)
        })
}

/// Every sample of a [`small_move`] (two ramps of at most 2 s and 2 s of
/// cruise: under 30 000 ticks at 4 kHz), bounded so that a stepper that
/// never stops fails the landing checks instead of hanging the test.
fn ticks_of(st: TrapezoidStepper) -> Vec<TrapezoidSample> {
    st.take(100_000).collect()
}

/// Whole steps moved in each phase, as the stepper labels its ticks.
fn phase_steps(samples: &[TrapezoidSample]) -> [i64; 3] {
    let mut n = [0; 3];
    for w in samples.windows(2) {
        let d = whole_steps(w[1].position) - whole_steps(w[0].position);
        let i = match w[1].phase {
            TrapezoidPhase::Accel => 0,
            TrapezoidPhase::Cruise => 1,
            TrapezoidPhase::Decel | TrapezoidPhase::Rest => 2,
        };
        n[i] += d;
    }
    n
}

/// The least distance a stepper still covers after a tick at velocity `w`
/// without passing the deceleration limit: the ticks w − d, w − 2d, ... up
/// to the first at or below the stop speed, from which it may stop at once.
fn least_stop(lim: TickLimits, w: i64) -> i128 {
    let (s, d) = (i128::from(lim.stop()), i128::from(lim.decel));
    let w = i128::from(w);
    if w <= s {
        return 0;
    }
    let ticks = (w - s).div_euclid(d) + i128::from((w - s).rem_euclid(d) != 0);
    // An arithmetic series: ticks terms from w − d down to w − ticks·d.
    ticks * (2 * w - d * (ticks + 1)) / 2
}

#[test]
fn least_stop_sums_the_braking_ticks() {
    // Checks the closed form the next property relies on against the sum.
    let mut cases = 0;
    for (start, decel) in [(0, 1), (3, 2), (5, 5), (2, 7), (0, 9)] {
        let lim = TickLimits {
            start,
            accel: 1,
            max: 100,
            decel,
        };
        for w in 0..=100 {
            let (mut v, mut sum) = (i128::from(w), 0);
            while v > i128::from(lim.stop()) {
                v -= i128::from(decel);
                sum += v;
            }
            assert_eq!(
                least_stop(lim, w),
                sum,
                "start {start}, decel {decel}, w {w}"
            );
            cases += 1;
        }
    }
    assert_eq!(cases, 505);
}

#[test]
fn a_deceleration_of_one_lsb_per_tick_still_lands() {
    // 1 step/s² at 1 MHz rounds to the least deceleration, one LSB a tick:
    // the ramp down is then one LSB at a time, and the search's lower bound
    // is the velocity less that one LSB.
    let p = params(0, 1, 1, 1, 1);
    let st = TrapezoidStepper::new(&p, 1_000_000).unwrap();
    assert_eq!(st.limits().decel, 1);
    let samples: Vec<_> = st.take(3_000_000).collect();
    let last = *samples.last().unwrap();
    assert_eq!(
        (last.position, last.velocity),
        (ONE, 0),
        "tick {}",
        last.tick
    );
    assert_eq!(last.phase, TrapezoidPhase::Rest);
    let decel_ticks = samples
        .windows(2)
        .filter(|w| w[1].velocity == w[0].velocity - 1)
        .count();
    assert!(decel_ticks > 1000, "{decel_ticks} ticks of one-LSB braking");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn stepper_takes_the_fastest_velocity_that_can_still_stop((p, tick) in small_move()) {
        let st = TrapezoidStepper::new(&p, tick).unwrap();
        let lim = st.limits();
        let target = i128::from(p.steps) * i128::from(ONE);
        let samples = ticks_of(st);
        for w in samples.windows(2) {
            let (s0, s1) = (w[0], w[1]);
            let reach = lim.max.min((s0.velocity + lim.accel).max(lim.start));
            let stops = |v: i64| i128::from(s0.position) + i128::from(v) + least_stop(lim, v) <= target;
            prop_assert!(stops(s1.velocity), "tick {}: {} cannot stop", s1.tick, s1.velocity);
            prop_assert!(s1.velocity == reach || !stops(s1.velocity + 1),
                "tick {}: {} taken, {} could still stop (reach {})",
                s1.tick, s1.velocity, s1.velocity + 1, reach);
            let last = s1.tick == samples.last().unwrap().tick;
            prop_assert_eq!(s1.phase == TrapezoidPhase::Rest, last, "tick {}", s1.tick);
        }
    }

    #[test]
    fn plan_counts_sum_to_the_target((p, _) in small_move()) {
        let pl = plan(&p).unwrap();
        let (v0, vt) = (u128::from(p.start_speed), u128::from(p.target_speed));
        let (a, d) = (u128::from(p.accel), u128::from(p.decel));
        let (na, nc, nd) = (u128::from(pl.accel_steps), u128::from(pl.cruise_steps), u128::from(pl.decel_steps));
        prop_assert_eq!(na + nc + nd, u128::from(p.steps));
        let peak = u128::from(pl.peak_speed);
        prop_assert!(peak <= vt && peak >= v0);
        if pl.triangular {
            prop_assert_eq!(nc, 0);
            // The ramps meet: v0² + 2a·n_acc = v0² + 2d·n_dec up to the floor
            // of n_acc, i.e. −(a + d) < a·n_acc − d·n_dec <= 0.
            let diff = (a * na) as i128 - (d * nd) as i128;
            prop_assert!(diff <= 0 && diff > -((a + d) as i128), "a·n_acc − d·n_dec = {}", diff);
            // Peak² within one point of acceleration of v0² + 2a·n_acc.
            prop_assert!(peak * peak <= v0 * v0 + 2 * a * na);
            prop_assert!((peak + 1) * (peak + 1) > v0 * v0 + 2 * a * na);
        } else {
            // Each ramp is the most points that do not pass the target speed.
            prop_assert!(v0 * v0 + 2 * a * na <= vt * vt);
            prop_assert!(v0 * v0 + 2 * a * (na + 1) > vt * vt);
            prop_assert!(v0 * v0 + 2 * d * nd <= vt * vt);
            prop_assert!(v0 * v0 + 2 * d * (nd + 1) > vt * vt);
        }
    }

    #[test]
    fn stepper_stays_within_limits_and_lands_exactly((p, tick) in small_move()) {
        let st = TrapezoidStepper::new(&p, tick).unwrap();
        let lim = st.limits();
        let samples = ticks_of(st);
        let first = samples[0];
        prop_assert_eq!((first.tick, first.position, first.velocity), (0, 0, 0));
        let last = *samples.last().unwrap();
        prop_assert_eq!(last.position, i64::from(p.steps) * ONE);
        prop_assert_eq!(whole_steps(last.position), i64::from(p.steps));
        prop_assert_eq!(last.velocity, 0);
        for (k, w) in samples.windows(2).enumerate() {
            let (s0, s1) = (w[0], w[1]);
            prop_assert_eq!(s1.tick, s0.tick + 1);
            prop_assert_eq!(s1.position, s0.position + s1.velocity);
            prop_assert!(s1.velocity >= 0 && s1.velocity <= lim.max, "speed {} > {}", s1.velocity, lim.max);
            let dv = s1.velocity - s0.velocity;
            // Up by at most the acceleration, or a start up to the start speed.
            prop_assert!(dv <= lim.accel || s1.velocity <= lim.start, "tick {}: +{}", k + 1, dv);
            // Down by at most the deceleration, except from at most the stop
            // speed: the final tick covers what is left, then the stop.
            let target = i64::from(p.steps) * ONE;
            prop_assert!(-dv <= lim.decel || (s0.velocity <= lim.stop() && s1.position == target),
                "tick {}: {}", k + 1, dv);
            // Moving the whole time between the first and the last sample.
            if s1.tick != last.tick && p.steps > 0 {
                prop_assert!(s1.velocity > 0, "stopped at tick {}", s1.tick);
            }
        }
    }

    #[test]
    fn stepper_phases_follow_the_plan((p, tick) in small_move()) {
        let pl = plan(&p).unwrap();
        let samples = ticks_of(TrapezoidStepper::new(&p, tick).unwrap());
        let got = phase_steps(&samples);
        prop_assert_eq!(got.iter().sum::<i64>(), i64::from(p.steps));
        // A ramp ends on a tick boundary (up to a tick at peak speed past the
        // continuous one) and sums its ticks' speeds where the plan
        // integrates (up to another tick); the cruise gives up what both
        // ramps take. Plus a step for each floor.
        let peak = i64::from(pl.peak_speed.div_ceil(tick));
        let want = [pl.accel_steps, pl.cruise_steps, pl.decel_steps].map(i64::from);
        for (i, tol) in [2 * peak + 2, 4 * peak + 2, 2 * peak + 2].into_iter().enumerate() {
            prop_assert!((got[i] - want[i]).abs() <= tol,
                "phase {}: {} steps, planned {} (tolerance {})", i, got[i], want[i], tol);
        }
    }
}
