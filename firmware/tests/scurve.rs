//! 7-segment S-curves (seed 004, steps 1-5).

use motionhdl_firmware::scurve::{
    braking_distance, Phase, SCurve, SCurveError, SCurveParams, SCurveSample, ACCEL_RANGE,
    DISTANCE_MAX, JERK_RANGE, MAX_RAMP_TICKS, VELOCITY_RANGE,
};
use motionhdl_firmware::{OutOfRange, ONE};
use proptest::prelude::*;

fn samples(p: SCurveParams) -> Vec<SCurveSample> {
    SCurve::new(p).unwrap().samples().collect()
}

/// Ticks spent in T1..T7 (index 1..=7).
fn phase_ticks(s: &[SCurveSample]) -> [u64; 8] {
    let mut n = [0; 8];
    for x in s {
        if let Some(i) = x.phase.number() {
            n[usize::from(i)] += 1;
        }
    }
    n
}

/// Limits with ramps of at most a few hundred ticks, and a distance in
/// either direction of at most 10^5 steps and about 2000 ticks of cruise.
fn moves() -> impl Strategy<Value = SCurveParams> {
    (1i64 << 16..1 << 34, 1i64..300, 1i64..300, -1.0f64..=1.0).prop_map(|(jerk, ka, kv, frac)| {
        // A/J and V/A, the ramp lengths in ticks, within 1..300.
        let accel = (jerk * ka).min(ACCEL_RANGE.1);
        let velocity = (accel * kv).min(VELOCITY_RANGE.1);
        let longest = velocity as f64 / ONE as f64 * (ka + kv + 2000) as f64;
        SCurveParams {
            jerk,
            accel,
            velocity,
            distance: (frac * longest.min(1e5)) as i64,
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn scurve_stays_within_limits_and_ends_exactly_on_target(p in moves()) {
        let s = samples(p);
        let dir = p.distance.signum();
        prop_assert_eq!(s[0], SCurveSample::default());
        let last = *s.last().unwrap();
        prop_assert_eq!(last.position, p.distance * ONE);
        prop_assert_eq!(last.steps(), p.distance);
        prop_assert_eq!((last.velocity, last.accel), (0, 0));
        // The last tick's jerk brings the deceleration back to 0: T7.
        let end_phase = if p.distance == 0 { Phase::Rest } else { Phase::DecreasingDecel };
        prop_assert_eq!(last.phase, end_phase);
        for w in s.windows(2) {
            let (s0, s1) = (w[0], w[1]);
            prop_assert_eq!(s1.tick, s0.tick + 1);
            // The discrete model: v is the tick's distance, a its change.
            prop_assert_eq!(s1.velocity, s1.position - s0.position);
            prop_assert_eq!(s1.accel, s1.velocity - s0.velocity);
            prop_assert!(s1.velocity.abs() <= p.velocity, "|v| {} > V {}", s1.velocity, p.velocity);
            prop_assert!(s1.accel.abs() <= p.accel, "|a| {} > A {}", s1.accel, p.accel);
            prop_assert!((s1.accel - s0.accel).abs() <= p.jerk,
                "|jerk| {} > J {} at tick {}", s1.accel - s0.accel, p.jerk, s1.tick);
            // Never backwards.
            prop_assert!(s1.velocity * dir >= 0);
            // Moving from the first tick to the target: no stop on the way.
            if s1.tick < last.tick && s1.position != last.position {
                prop_assert!(s1.velocity != 0);
            }
        }
    }

    #[test]
    fn scurve_phases_run_in_order_with_symmetric_jerk_ramps(p in moves()) {
        let s = samples(p);
        let mut last = 0;
        for x in &s {
            if let Some(n) = x.phase.number() {
                prop_assert!(n >= last, "T{} after T{} at tick {}", n, last, x.tick);
                last = n;
            }
        }
        // T1 = T3 and T5 = T7: one jerk ramps acceleration up and down; a
        // tick's rounding may split a ramp's last step.
        let t = phase_ticks(&s);
        prop_assert!(t[1].abs_diff(t[3]) <= 1, "T1 {} T3 {}", t[1], t[3]);
        prop_assert!(t[5].abs_diff(t[7]) <= 1, "T5 {} T7 {}", t[5], t[7]);
        if p.distance == 0 {
            prop_assert_eq!(s.len(), 1);
        }
    }

    #[test]
    fn long_moves_reach_the_limits_and_brake_where_the_distance_runs_out(
        jerk in 1i64 << 20..1 << 30, ka in 5i64..60, extra in 5i64..100,
    ) {
        let kv = ka + extra;
        // Long enough to cruise: distance = 4 × the ramps' distance, or more.
        let (accel, velocity) = (jerk * ka, jerk * ka * kv);
        let ramp_ticks = (ka + kv) as f64;
        let ramp = (velocity as f64 / ONE as f64) * ramp_ticks;
        let distance = (4.0 * ramp) as i64 + 100;
        let p = SCurveParams { jerk, accel, velocity, distance };
        let c = SCurve::new(p).unwrap();
        let s: Vec<_> = c.samples().collect();
        let t = phase_ticks(&s);
        // All seven segments; T2 and T6 since V/A > A/J.
        for (i, &n) in t.iter().enumerate().skip(1) {
            prop_assert!(n > 0, "no T{}", i);
        }
        // The jerk ramp to A takes A/J ticks (T1 counts from the first tick).
        prop_assert!((t[1] as i64 - ka).abs() <= 1, "T1 {} vs A/J {}", t[1], ka);
        let vmax = s.iter().map(|x| x.velocity).max().unwrap();
        let amax = s.iter().map(|x| x.accel).max().unwrap();
        // Within a millionth (the final scaling) and a few LSB of the limits.
        prop_assert!(vmax as f64 >= velocity as f64 * (1.0 - 1e-6));
        prop_assert!(amax as f64 >= accel as f64 * (1.0 - 1e-6) - 4.0);
        // Braking from the cruise is the acceleration law mirrored, so it
        // takes as many ticks; the first braking tick's partial jerk may
        // shift its end by one.
        let (up, down) = (t[1] + t[2] + t[3], t[5] + t[6] + t[7]);
        prop_assert!(up.abs_diff(down) <= 1, "accelerating {} ticks, braking {}", up, down);
        let decel_at = s[c.decel_tick() as usize - 1].position;
        // Step 2's comparison, at the state where the cruise ends: the
        // remaining distance is within one tick at V of the braking distance.
        let remaining = p.distance * ONE - decel_at;
        let dec = braking_distance(velocity, 0, jerk, accel);
        prop_assert!((i128::from(remaining) - dec).abs() <= i128::from(2 * velocity),
            "remaining {} vs dec {}", remaining, dec);
    }
}

#[test]
fn the_direction_is_the_sign_of_the_distance() {
    let p = SCurveParams {
        jerk: ONE / 100,
        accel: ONE / 5,
        velocity: 20 * ONE,
        distance: 3000,
    };
    let fwd = samples(p);
    let back = samples(SCurveParams {
        distance: -3000,
        ..p
    });
    assert_eq!(fwd.len(), back.len());
    let mut compared = 0;
    for (f, b) in fwd.iter().zip(&back) {
        assert_eq!(
            (f.position, f.velocity, f.accel, f.phase),
            (-b.position, -b.velocity, -b.accel, b.phase)
        );
        compared += 1;
    }
    assert_eq!(compared, fwd.len());
    assert_eq!(back.last().unwrap().steps(), -3000);
}

#[test]
fn a_one_step_move_never_reaches_the_limits() {
    // J = 0.01 steps/tick³, A = 0.2, V = 20: one step is far too short to
    // reach A (which takes 20 ticks of jerk) or V.
    let p = SCurveParams {
        jerk: ONE / 100,
        accel: ONE / 5,
        velocity: 20 * ONE,
        distance: 1,
    };
    let s = samples(p);
    let t = phase_ticks(&s);
    assert_eq!((t[2], t[4], t[6]), (0, 0, 0), "{t:?}");
    assert!(s.iter().all(|x| x.accel.abs() < p.accel / 2));
    assert_eq!(s.last().unwrap().position, ONE);
    // A jerk-limited triangle of distance 1 at J: four ramps of about
    // (1/(2J))^(1/3) = 3.7 ticks each.
    assert!((12..=20).contains(&s.len()), "{} samples", s.len());
}

#[test]
fn bad_parameters_are_named_with_their_range() {
    let good = SCurveParams {
        jerk: ONE / 100,
        accel: ONE / 5,
        velocity: 20 * ONE,
        distance: 100,
    };
    let cases = [
        (SCurveParams { jerk: 0, ..good }, "jerk", 0, JERK_RANGE),
        (
            SCurveParams {
                accel: ACCEL_RANGE.1 + 1,
                ..good
            },
            "accel",
            ACCEL_RANGE.1 + 1,
            ACCEL_RANGE,
        ),
        (
            SCurveParams {
                velocity: -5,
                ..good
            },
            "velocity",
            -5,
            VELOCITY_RANGE,
        ),
        (
            SCurveParams {
                distance: DISTANCE_MAX + 1,
                ..good
            },
            "distance",
            DISTANCE_MAX + 1,
            (-DISTANCE_MAX, DISTANCE_MAX),
        ),
    ];
    let mut checked = 0;
    for (p, name, value, (min, max)) in cases {
        let e = SCurve::new(p).unwrap_err();
        assert_eq!(
            e,
            SCurveError::OutOfRange(OutOfRange {
                name,
                value,
                min,
                max
            })
        );
        assert_eq!(
            e.to_string(),
            format!("{name} = {value} out of range {min}..={max}")
        );
        checked += 1;
    }
    assert_eq!(checked, 4);
    // 2^13 ticks of jerk to reach A.
    let slow = SCurveParams {
        jerk: JERK_RANGE.0,
        accel: JERK_RANGE.0 << 13,
        ..good
    };
    match SCurve::new(slow) {
        Err(SCurveError::TooLong { ramp_ticks, max }) => {
            assert_eq!(max, MAX_RAMP_TICKS);
            assert!(ramp_ticks > MAX_RAMP_TICKS);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn physical_units_convert_per_tick() {
    // At 1 kHz: 1e9 steps/s³ = 1 step/tick³, 2e6 steps/s² = 2 steps/tick²,
    // 5000 steps/s = 5 steps/tick.
    let p = SCurveParams::from_physical(1e9, 2e6, 5000.0, -7, 1000.0);
    assert_eq!(
        (p.jerk, p.accel, p.velocity, p.distance),
        (ONE, 2 * ONE, 5 * ONE, -7)
    );
}
