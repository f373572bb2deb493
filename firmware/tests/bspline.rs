//! Cubic uniform B-spline fine interpolation (seed 002, section 3.1).

use motionhdl_firmware::bspline::{clamped, fine_len, fine_points, FineInterpolator, Span};
use proptest::prelude::*;

type P3 = [f64; 3];

fn close(a: &[f64], b: &[f64], scale: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= 1e-9 * scale.max(1.0))
}

fn scale_of(p: &[P3]) -> f64 {
    p.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The basis form 1/6[(1−t)³P0 + (3t³−6t²+4)P1 + (−3t³+3t²+3t+1)P2 + t³P3].
fn basis(p: &[P3; 4], t: f64) -> P3 {
    let b = [
        (1.0 - t).powi(3),
        3.0 * t.powi(3) - 6.0 * t * t + 4.0,
        -3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0,
        t.powi(3),
    ];
    std::array::from_fn(|i| (0..4).map(|k| b[k] * p[k][i]).sum::<f64>() / 6.0)
}

fn point() -> impl Strategy<Value = P3> {
    prop::array::uniform3(-1e4f64..1e4)
}

fn span_points() -> impl Strategy<Value = [P3; 4]> {
    prop::array::uniform4(point())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn the_seed_power_form_is_the_basis_form(p in span_points(), t in 0.0f64..=1.0) {
        let s = Span::new(&p);
        prop_assert!(close(&s.point(t), &basis(&p, t), scale_of(&p)));
    }

    #[test]
    fn span_ends_are_the_known_averages(p in span_points()) {
        let s = Span::new(&p);
        let start: P3 = std::array::from_fn(|i| (p[0][i] + 4.0 * p[1][i] + p[2][i]) / 6.0);
        let end: P3 = std::array::from_fn(|i| (p[1][i] + 4.0 * p[2][i] + p[3][i]) / 6.0);
        prop_assert!(close(&s.point(0.0), &start, scale_of(&p)));
        prop_assert!(close(&s.point(1.0), &end, scale_of(&p)));
        // Derivatives at t = 0 from the basis: P' = (P2 − P0)/2,
        // P'' = P0 − 2P1 + P2.
        let d1: P3 = std::array::from_fn(|i| (p[2][i] - p[0][i]) / 2.0);
        let d2: P3 = std::array::from_fn(|i| p[0][i] - 2.0 * p[1][i] + p[2][i]);
        prop_assert!(close(&s.derivative(0.0), &d1, scale_of(&p)));
        prop_assert!(close(&s.second_derivative(0.0), &d2, scale_of(&p)));
    }

    /// C0, C1 and C2 where span s (points s..s+4) meets span s+1.
    #[test]
    fn joints_are_c2(coarse in prop::collection::vec(point(), 5..12)) {
        let scale = scale_of(&coarse);
        let spans: Vec<Span<3>> = coarse
            .windows(4)
            .map(|w| Span::new(&[w[0], w[1], w[2], w[3]]))
            .collect();
        let mut joints = 0;
        for pair in spans.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            prop_assert!(close(&a.point(1.0), &b.point(0.0), scale));
            prop_assert!(close(&a.derivative(1.0), &b.derivative(0.0), scale));
            prop_assert!(close(&a.second_derivative(1.0), &b.second_derivative(0.0), scale));
            joints += 1;
        }
        prop_assert_eq!(joints, coarse.len() - 4);
    }

    /// The forward-difference iterator gives the span formula at t = i/n.
    #[test]
    fn fine_points_are_the_spans_sampled(coarse in prop::collection::vec(point(), 4..9), n in 1u32..200) {
        let fine = fine_points(&coarse, n);
        prop_assert_eq!(fine.len(), (coarse.len() - 3) * n as usize + 1);
        prop_assert_eq!(fine.len(), fine_len(coarse.len(), n));
        let scale = scale_of(&coarse);
        for (k, got) in fine.iter().enumerate() {
            let (s, i) = (k / n as usize, k % n as usize);
            // The very last point is the last span at t = 1.
            let (s, t) = if s == coarse.len() - 3 { (s - 1, 1.0) } else { (s, i as f64 / f64::from(n)) };
            let w = &coarse[s..s + 4];
            let want = Span::new(&[w[0], w[1], w[2], w[3]]).point(t);
            prop_assert!(close(got, &want, scale), "point {}: {:?} vs {:?}", k, got, want);
        }
    }
}

#[test]
fn size_hint_is_exact_and_short_inputs_give_nothing() {
    let coarse: Vec<[f64; 2]> = (0..8).map(|i| [f64::from(i), f64::from(i * i)]).collect();
    let mut cases = 0;
    for len in 0..=coarse.len() {
        for n in 0..=12 {
            let mut it = FineInterpolator::new(&coarse[..len], n);
            let want = fine_len(len, n);
            assert_eq!(
                want,
                if len < 4 || n == 0 {
                    0
                } else {
                    (len - 3) * n as usize + 1
                }
            );
            for left in (0..=want).rev() {
                assert_eq!(it.size_hint(), (left, Some(left)));
                assert_eq!(it.next().is_some(), left > 0);
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 9 * 13);
}

#[test]
fn a_straight_line_is_reproduced_evenly() {
    // Evenly spaced collinear points: the spline is the line itself, run at
    // a constant pace (B-splines reproduce linear functions).
    let coarse: Vec<[f64; 2]> = (0..6)
        .map(|i| [10.0 * f64::from(i), 5.0 - 2.0 * f64::from(i)])
        .collect();
    let fine = fine_points(&coarse, 10);
    assert_eq!(fine.len(), 3 * 10 + 1);
    for (k, p) in fine.iter().enumerate() {
        // From coarse point 1 (the first span's start) one unit per fine point.
        let x = 10.0 + k as f64;
        assert!(close(p, &[x, 5.0 - 2.0 * x / 10.0], 100.0), "{k}: {p:?}");
    }
}

#[test]
fn clamped_curves_start_and_end_on_the_coarse_points() {
    let coarse: Vec<P3> = vec![
        [0.0, 0.0, 0.0],
        [3.0, 1.0, -2.0],
        [4.0, 5.0, 1.0],
        [9.0, 2.0, 0.5],
    ];
    let ext = clamped(&coarse);
    assert_eq!(ext.len(), coarse.len() + 4);
    let fine = fine_points(&ext, 16);
    assert!(close(&fine[0], &coarse[0], 10.0));
    assert!(close(fine.last().unwrap(), coarse.last().unwrap(), 10.0));
    assert!(clamped::<3>(&[]).is_empty());
}
