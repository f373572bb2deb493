//! Cubic uniform B-spline fine interpolation of the TMS320C32 DSP card (seed
//! 002, section 3.1): the host sends coarse points, the DSP refines each
//! span between four neighbours P0..P3 into n fine points with
//!
//! ```text
//! P(t) = (P0 + 4P1 + P2)/6 + (−P0 + P2)/2·t + (P0 − 2P1 + P2)/2·t²
//!        + (−P0 + 3P1 − 3P2 + P3)/6·t³,        0 <= t <= 1
//! ```
//!
//! the seed's power form of the basis form
//! 1/6[(1−t)³P0 + (3t³−6t²+4)P1 + (−3t³+3t²+3t+1)P2 + t³P3]. Span s uses
//! coarse points s..s+4, so the curve runs from (P0+4P1+P2)/6 to
//! (P1+4P2+P3)/6 per span and is C2 across spans; it approximates rather
//! than passes through the coarse points ([`clamped`] repeats the end points
//! so it starts and ends on them).
//!
//! Points are `[f64; N]` for N axes. `f64` because the TMS320C32 is a
//! floating-point DSP; the per-point work is the forward-difference update a
//! DSP would do (three additions per axis), restarted from the exact
//! coefficients at every span so that rounding does not build up.

use core::array::from_fn;

/// The power-form coefficients of one span, per axis:
/// `P(t) = c[0] + c[1]·t + c[2]·t² + c[3]·t³`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span<const N: usize> {
    pub c: [[f64; N]; 4],
}

impl<const N: usize> Span<N> {
    /// The span of control points P0..P3 (the seed's formula).
    pub fn new(p: &[[f64; N]; 4]) -> Self {
        let [p0, p1, p2, p3] = p;
        Self {
            c: [
                from_fn(|i| (p0[i] + 4.0 * p1[i] + p2[i]) / 6.0),
                from_fn(|i| (-p0[i] + p2[i]) / 2.0),
                from_fn(|i| (p0[i] - 2.0 * p1[i] + p2[i]) / 2.0),
                from_fn(|i| (-p0[i] + 3.0 * p1[i] - 3.0 * p2[i] + p3[i]) / 6.0),
            ],
        }
    }

    /// P(t).
    pub fn point(&self, t: f64) -> [f64; N] {
        let c = &self.c;
        from_fn(|i| ((c[3][i] * t + c[2][i]) * t + c[1][i]) * t + c[0][i])
    }

    /// dP/dt.
    pub fn derivative(&self, t: f64) -> [f64; N] {
        let c = &self.c;
        from_fn(|i| (3.0 * c[3][i] * t + 2.0 * c[2][i]) * t + c[1][i])
    }

    /// d²P/dt².
    pub fn second_derivative(&self, t: f64) -> [f64; N] {
        let c = &self.c;
        from_fn(|i| 6.0 * c[3][i] * t + 2.0 * c[2][i])
    }
}

/// Number of fine points [`FineInterpolator`] yields for `coarse` points and
/// `n` per span: n per span plus the last span's end, or 0 with fewer than
/// four coarse points or n = 0.
pub fn fine_len(coarse: usize, n: u32) -> usize {
    if coarse < 4 || n == 0 {
        0
    } else {
        (coarse - 3) * n as usize + 1
    }
}

/// The fine points of a coarse sequence: each span at t = 0, 1/n, ...,
/// (n−1)/n, and the last span also at t = 1.
#[derive(Clone, Debug)]
pub struct FineInterpolator<'a, const N: usize> {
    coarse: &'a [[f64; N]],
    n: u32,
    span: usize,
    i: u32,
    /// Forward differences: value, Δ, Δ², Δ³.
    f: [[f64; N]; 4],
}

impl<'a, const N: usize> FineInterpolator<'a, N> {
    pub fn new(coarse: &'a [[f64; N]], n: u32) -> Self {
        let mut it = Self {
            coarse,
            n,
            span: 0,
            i: 0,
            f: [[0.0; N]; 4],
        };
        if fine_len(coarse.len(), n) > 0 {
            it.start_span();
        }
        it
    }

    fn spans(&self) -> usize {
        self.coarse.len().saturating_sub(3)
    }

    fn start_span(&mut self) {
        let s = self.span;
        let p = [
            self.coarse[s],
            self.coarse[s + 1],
            self.coarse[s + 2],
            self.coarse[s + 3],
        ];
        let c = Span::new(&p).c;
        let h = 1.0 / f64::from(self.n);
        let (h2, h3) = (h * h, h * h * h);
        self.f = [
            c[0],
            from_fn(|i| c[1][i] * h + c[2][i] * h2 + c[3][i] * h3),
            from_fn(|i| 2.0 * c[2][i] * h2 + 6.0 * c[3][i] * h3),
            from_fn(|i| 6.0 * c[3][i] * h3),
        ];
        self.i = 0;
    }
}

impl<const N: usize> Iterator for FineInterpolator<'_, N> {
    type Item = [f64; N];

    fn next(&mut self) -> Option<[f64; N]> {
        if self.span >= self.spans() || self.n == 0 {
            return None;
        }
        let out = self.f[0];
        self.i += 1;
        if self.i < self.n {
            for k in 0..N {
                self.f[0][k] += self.f[1][k];
                self.f[1][k] += self.f[2][k];
                self.f[2][k] += self.f[3][k];
            }
        } else if self.span + 1 < self.spans() {
            self.span += 1;
            self.start_span();
        } else if self.i == self.n {
            // The last span's end, from its exact coefficients.
            let s = self.span;
            let p = [
                self.coarse[s],
                self.coarse[s + 1],
                self.coarse[s + 2],
                self.coarse[s + 3],
            ];
            self.f[0] = Span::new(&p).point(1.0);
        } else {
            self.span += 1;
        }
        Some(out)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = if self.span >= self.spans() {
            0
        } else {
            fine_len(self.coarse.len(), self.n) - (self.span * self.n as usize + self.i as usize)
        };
        (left, Some(left))
    }
}

/// All fine points of `coarse`, `n` per span.
#[cfg(feature = "alloc")]
pub fn fine_points<const N: usize>(coarse: &[[f64; N]], n: u32) -> alloc::vec::Vec<[f64; N]> {
    FineInterpolator::new(coarse, n).collect()
}

/// `coarse` with its first and last points repeated twice more, so that the
/// curve starts on the first point and ends on the last: (P + 4P + P)/6 = P.
#[cfg(feature = "alloc")]
pub fn clamped<const N: usize>(coarse: &[[f64; N]]) -> alloc::vec::Vec<[f64; N]> {
    let (Some(first), Some(last)) = (coarse.first(), coarse.last()) else {
        return alloc::vec::Vec::new();
    };
    let mut v = alloc::vec::Vec::with_capacity(coarse.len() + 4);
    v.extend([*first, *first]);
    v.extend_from_slice(coarse);
    v.extend([*last, *last]);
    v
}
