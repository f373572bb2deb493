//! Incremental PID (seed 002, section 3.2).

use motionhdl_firmware::pid::{dac_offset_binary, IncrementalPid, PidGains, Q16_ONE};
use proptest::prelude::*;

fn gains(kp: f64, ti_ratio: f64, td_ratio: f64) -> PidGains {
    let q = |x: f64| (x * f64::from(Q16_ONE)) as i32;
    PidGains {
        kp: q(kp),
        ti_ratio: q(ti_ratio),
        td_ratio: q(td_ratio),
    }
}

fn run(pid: &mut IncrementalPid, errors: &[i32]) -> Vec<i16> {
    errors.iter().map(|&e| pid.update(e)).collect()
}

#[test]
fn hand_computed_sequence() {
    // Kp = 2, τ/τi = 0.5, τd/τ = 0.25 (exact in Q16.16).
    // u(k) = u(k−1) + 2·{e − e1 + 0.5e + 0.25(e − 2e1 + e2)}
    // k0: e=100, e1=0,   e2=0:   100 + 50 + 0.25·100        = 175   → u = 350
    // k1: e=50,  e1=100, e2=0:   −50 + 25 + 0.25·(−150)     = −62.5 → u = 225
    // k2: e=−20, e1=50,  e2=100: −70 − 10 + 0.25·(−20)      = −85   → u = 55
    // k3: e=0,   e1=−20, e2=50:  20 + 0 + 0.25·90           = 42.5  → u = 140
    let mut pid = IncrementalPid::new(gains(2.0, 0.5, 0.25));
    assert_eq!(run(&mut pid, &[100, 50, -20, 0]), [350, 225, 55, 140]);
    assert_eq!(pid.errors(), [0, -20]);
    assert_eq!(pid.output_q16(), 140 << 16);
}

#[test]
fn increments_below_one_code_accumulate() {
    // Kp = 1, τ/τi = 0.25, no derivative; a constant error of 1.
    // k0: 1 − 0 + 0.25 = 1.25 → u = 1.25 → 1
    // then 0 + 0.25 each: 1.5 → 2 (half up), 1.75 → 2, 2.0 → 2, 2.25 → 2,
    // 2.5 → 3. An integer u would stay at 1.
    let mut pid = IncrementalPid::new(gains(1.0, 0.25, 0.0));
    assert_eq!(run(&mut pid, &[1; 6]), [1, 2, 2, 2, 2, 3]);
}

#[test]
fn output_clamps_at_both_dac_limits_without_wind_up() {
    // Pure proportional: u(k) = u(k−1) + (e − e1), i.e. u = e unclamped.
    let p = gains(1.0, 0.0, 0.0);
    let mut pid = IncrementalPid::new(p);
    // 40000 is past the top: 32767. Holding it changes nothing; the first
    // step down leaves the limit at once (an unclamped u would sit at 39999).
    assert_eq!(
        run(&mut pid, &[40_000, 40_000, 39_999]),
        [32767, 32767, 32766]
    );
    pid.reset();
    assert_eq!(pid.errors(), [0, 0]);
    assert_eq!(
        run(&mut pid, &[-40_000, -40_000, -39_999]),
        [-32768, -32768, -32767]
    );
    // An integral term pushing on at a limit stays there.
    let mut pid = IncrementalPid::new(gains(100.0, 1.0, 0.0));
    let out = run(&mut pid, &[i32::MAX; 5]);
    assert!(out.iter().all(|&u| u == i16::MAX), "{out:?}");
    let out = run(&mut pid, &[i32::MIN; 5]);
    assert!(out.iter().all(|&u| u == i16::MIN), "{out:?}");
}

#[test]
fn dac7744_straight_binary() {
    // Bipolar range: 0x0000 = −FS, 0x8000 = 0 V, 0xFFFF = +FS − 1 LSB.
    let cases = [
        (i16::MIN, 0x0000),
        (-1, 0x7FFF),
        (0, 0x8000),
        (1, 0x8001),
        (i16::MAX, 0xFFFF),
    ];
    for (code, binary) in cases {
        assert_eq!(dac_offset_binary(code), binary, "{code}");
    }
    // Monotonic over every code.
    let mut checked = 0;
    for c in i16::MIN..i16::MAX {
        assert_eq!(dac_offset_binary(c + 1), dac_offset_binary(c) + 1);
        checked += 1;
    }
    assert_eq!(checked, 65535);
}

#[test]
fn gains_from_times() {
    // Kp = 2, τ = 1 ms, τi = 4 ms, τd = 0.5 ms: τ/τi = 0.25, τd/τ = 0.5.
    let g = PidGains::from_times(2.0, 1e-3, 4e-3, 0.5e-3);
    assert_eq!((g.kp, g.ti_ratio, g.td_ratio), (2 << 16, 1 << 14, 1 << 15));
    // τi = ∞: no integral term.
    assert_eq!(
        PidGains::from_times(1.0, 1.0, f64::INFINITY, 0.0).ti_ratio,
        0
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Against the seed's formula in f64 (also clamped): the fixed point
    /// rounds each increment to 2^-16, so after k steps u is within k·2^-17.
    #[test]
    fn follows_the_formula_in_floating_point(
        kp in -(4 << 16)..(4i32 << 16), ti in 0..(1i32 << 16), td in 0..(4i32 << 16),
        errors in prop::collection::vec(-3000i32..3000, 1..60),
    ) {
        let g = PidGains { kp, ti_ratio: ti, td_ratio: td };
        let (kp, ti, td) = [kp, ti, td].map(|x| f64::from(x) / 65536.0).into();
        let mut pid = IncrementalPid::new(g);
        let (mut u, mut e1, mut e2) = (0.0f64, 0.0, 0.0);
        for (k, &e) in errors.iter().enumerate() {
            let out = pid.update(e);
            let e = f64::from(e);
            u += kp * (e - e1 + ti * e + td * (e - 2.0 * e1 + e2));
            u = u.clamp(-32768.0, 32767.0);
            (e2, e1) = (e1, e);
            let got = pid.output_q16() as f64 / 65536.0;
            let tol = (k + 1) as f64 / 131072.0 + 1e-9;
            prop_assert!((got - u).abs() <= tol, "step {}: {} vs {}", k, got, u);
            prop_assert!((f64::from(out) - u).abs() <= 0.5 + tol);
        }
    }
}

#[test]
fn from_times_rounds_half_away_from_zero_on_both_sides() {
    // Kp = ±1.75 LSB of Q16.16: ±2 (rounded away from zero), not ±1.
    let lsb = 1.0 / f64::from(Q16_ONE);
    let g = |kp: f64| PidGains::from_times(kp, 1.0, f64::INFINITY, 0.0);
    assert_eq!(g(1.75 * lsb).kp, 2);
    assert_eq!(g(-1.75 * lsb).kp, -2);
    assert_eq!(g(-1.25 * lsb).kp, -1);
    assert_eq!(g(-2.5 * lsb).kp, -3);
    // The gains the controller was made with are the ones it reports.
    let gains = PidGains::from_times(3.5, 1.0, 4.0, 0.5);
    assert_eq!(IncrementalPid::new(gains).gains(), gains);
}
