//! S-curves planned as at most 7 segments with a jerk, run through the
//! model's move engine and pulse generator: the end position exact, and the
//! commanded position within one step of the plan at every clock.

use motionhdl_firmware::scurve_segments::{plan, EngineLimits, Plan, PlanError};
use motionhdl_model::pulse_generator::{
    MoveEngine, PulseGenerator, PulseInputs, Request, StepTiming, ACCEL_FRAC_BITS,
};
use proptest::prelude::*;

const ONE_STEP: i128 = 1 << 64;

/// What a model run saw: clocks; the largest |plan − engine| with the
/// engine's position continuous (steps commanded + NCO phase / 2^32), and
/// the range of plan − steps commanded (2^-64 steps); the end position;
/// the largest |rate| and |accel| the engine ran at (its registers,
/// fraction bits included).
#[derive(Debug, Default)]
struct Run {
    clocks: u64,
    drift: i128,
    lead: (i128, i128),
    position: i64,
    top_rate: i64,
    top_accel: i64,
}

/// Pushes every segment (7 fit the FIFO), runs the axis and compares the
/// steps it commands, clock by clock, with `plan.position`.
fn run_model(plan: &Plan) -> Run {
    if plan.segments.is_empty() {
        return Run::default();
    }
    let timing = StepTiming {
        step_len: 1,
        step_space: 1,
        dir_setup: 1,
        dir_hold: 1,
    };
    let (mut eng, mut gen) = (MoveEngine::default(), PulseGenerator::new());
    for seg in &plan.segments {
        eng.clock(false, false, false, Some(*seg));
    }
    let (mut commanded, mut first_load, mut k) = (0i64, None::<u64>, 0u64);
    let mut run = Run::default();
    loop {
        let inputs = PulseInputs {
            enable: true,
            halt: false,
            rate: eng.rate(),
            timing,
        };
        let (request, blocked) = gen.request(&inputs);
        if let Some(start) = first_load {
            let planned = plan.position(k - start);
            // In the direction of the move.
            let lead = (planned - i128::from(commanded) * ONE_STEP) * i128::from(plan.direction);
            let phase = i128::from(gen.phase) << 32;
            run.drift = run.drift.max((lead - phase).abs());
            run.lead = (run.lead.0.min(lead), run.lead.1.max(lead));
        }
        commanded += match request {
            Request::Up => 1,
            Request::Down => -1,
            Request::None => 0,
        };
        let was_active = eng.active();
        eng.clock(true, request != Request::None, !blocked, None);
        gen.clock(&inputs, false);
        let p = eng.probe();
        let wide = |x: u64| ((x << 16) as i64 >> 16).abs();
        run.top_rate = run.top_rate.max(wide(p.rate));
        run.top_accel = run.top_accel.max(wide(p.accel));
        if first_load.is_none() && !was_active && eng.active() {
            first_load = Some(k);
        }
        k += 1;
        if first_load.is_some() && eng.level() == 0 && !eng.active() {
            break;
        }
        assert!(k < 1 << 28, "the move does not end");
    }
    run.clocks = k - first_load.unwrap();
    // Let the queued steps out.
    let idle = PulseInputs {
        enable: true,
        halt: false,
        rate: 0,
        timing,
    };
    while gen.busy() {
        gen.clock(&idle, false);
    }
    run.position = i64::from(gen.position as i32);
    run
}

/// The continuous S-curve's duration for the limits, clocks, at the
/// steepest jerk a ramp from rest can end on a step before passing the
/// acceleration limit, (A³/6)^(1/2) (the planner's bound; a steeper jerk
/// would reach A before the first step).
fn ideal_clocks(d: f64, lim: &EngineLimits) -> f64 {
    let a = f64::from(lim.accel) * 2f64.powi(-48);
    let j = (f64::from(lim.jerk) * 2f64.powi(-64)).min((a * a * a / 6.0).sqrt());
    let v = f64::from(lim.rate) * 2f64.powi(-32);
    let mut t1 = (a / j).min((v / j).sqrt());
    let mut t2 = (v / (j * t1) - t1).max(0.0);
    let ramp = j * t1 * (t1 + t2) * (2.0 * t1 + t2);
    if ramp > d {
        t2 = ((t1 * t1 + 4.0 * d / (j * t1)).sqrt() - 3.0 * t1).max(0.0) / 2.0;
        if t2 <= 0.0 {
            t1 = (d / (2.0 * j)).cbrt();
        }
        return 2.0 * (2.0 * t1 + t2);
    }
    2.0 * (2.0 * t1 + t2) + (d - ramp) / v
}

fn check(distance: i64, lim: EngineLimits) -> Result<Run, TestCaseError> {
    let p = plan(distance, lim).unwrap();
    prop_assert!(p.segments.len() <= 7, "{} segments", p.segments.len());
    let total: i64 = p
        .segments
        .iter()
        .map(|s| i64::from(s.steps) * p.direction)
        .sum();
    prop_assert_eq!(total, distance);
    for s in &p.segments {
        prop_assert!(s.steps > 0 && s.jerk.abs() <= lim.jerk, "{:?}", s);
    }
    let run = run_model(&p);
    prop_assert_eq!(run.position, distance);
    // The engine goes idle on the clock after the last step, as planned.
    prop_assert_eq!(run.clocks, p.clocks, "{:?}", p);
    // The engine follows the plan but for its registers' floors (< 2^-32
    // steps a clock), and its step count trails its continuous position by
    // less than one step: so the count is within one step of the plan, to
    // the drift.
    let steps = |x: i128| x as f64 / ONE_STEP as f64;
    prop_assert!(
        run.drift < ONE_STEP / 1000,
        "drift {:.6} steps",
        steps(run.drift)
    );
    let (low, high) = (-run.drift, ONE_STEP + run.drift);
    prop_assert!(
        run.lead.0 >= low && run.lead.1 <= high,
        "plan − steps in {:.4}..{:.4}, drift {:.4}",
        steps(run.lead.0),
        steps(run.lead.1),
        steps(run.drift)
    );
    // The limits hold on the engine's own registers, to the part of a
    // step a phase ends late by (measured: rate 1.0002, accel 1.0037 of
    // the limit at worst).
    let rate_top = i64::from(lim.rate) << ACCEL_FRAC_BITS;
    let accel_top = i64::from(lim.accel) << ACCEL_FRAC_BITS;
    prop_assert!(
        run.top_rate <= rate_top + rate_top / 200,
        "rate {} of {}",
        run.top_rate,
        rate_top
    );
    prop_assert!(
        run.top_accel <= accel_top + accel_top / 100,
        "accel {} of {}",
        run.top_accel,
        accel_top
    );
    let ideal = ideal_clocks(distance.unsigned_abs() as f64, &lim);
    prop_assert!(
        (run.clocks as f64) < 1.1 * ideal + 200.0,
        "{} clocks, the continuous S-curve {:.0}",
        run.clocks,
        ideal
    );
    Ok(run)
}

/// Limits at 50 MHz that keep moves of up to 20 000 steps within about
/// 2·10^7 clocks: 50..500 kHz, 10^6..10^8 steps/s², 10^8..10^11 steps/s³.
fn limits() -> impl Strategy<Value = EngineLimits> {
    (50_000f64..500_000.0, 6f64..8.0, 8f64..11.0)
        .prop_map(|(v, a, j)| EngineLimits::from_physical(v, 10f64.powf(a), 10f64.powf(j), 50e6))
}

proptest! {
    // 16 random moves (each up to 2·10^7 model clocks): 48 took 162 s of
    // CI; the fixed long move below covers the 20 000-step cruise.
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn scurves_land_exactly_within_one_step_of_the_plan(
        distance in prop_oneof![-4000i64..=4000, 4000i64..20_000], lim in limits(),
    ) {
        check(distance, lim)?;
    }
}

#[test]
fn a_long_move_cruises_and_lands() {
    // 20 000 steps at up to 200 kHz, 2·10^6 steps/s², 10^9 steps/s³:
    // about 0.2 s, 10^7 clocks.
    let lim = EngineLimits::from_physical(200_000.0, 2e6, 1e9, 50e6);
    let p = plan(20_000, lim).unwrap();
    assert_eq!(p.segments.len(), 7, "{:?}", p.segments);
    let jerks: Vec<i32> = p.segments.iter().map(|s| s.jerk.signum()).collect();
    assert_eq!(jerks, [1, 0, -1, 0, -1, 0, 1]);
    check(20_000, lim).unwrap();
    // Backwards, the mirror image (to a few clocks: the engine floors
    // negative registers toward −∞, so backwards their magnitudes round
    // up, and the plan follows that).
    let q = plan(-20_000, lim).unwrap();
    assert_eq!(q.segments.len(), 7);
    assert!(
        q.clocks.abs_diff(p.clocks) < p.clocks / 100,
        "{} {}",
        q.clocks,
        p.clocks
    );
    check(-20_000, lim).unwrap();
}

#[test]
fn bad_limits_are_refused() {
    let lim = EngineLimits::from_physical(200_000.0, 2e6, 1e9, 50e6);
    match plan(10, EngineLimits { jerk: 0, ..lim }) {
        Err(PlanError::OutOfRange(e)) => {
            assert_eq!((e.name, e.value, e.min), ("jerk", 0, 1));
        }
        other => panic!("{other:?}"),
    }
    match plan(i64::from(i32::MAX) + 1, lim) {
        Err(PlanError::OutOfRange(e)) => assert_eq!(e.name, "distance"),
        other => panic!("{other:?}"),
    }
    let p = plan(0, lim).unwrap();
    assert!(p.segments.is_empty() && p.clocks == 0);
}
