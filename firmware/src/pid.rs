//! Incremental (velocity-form) PID of the TMS320C32 DSP card (seed 002,
//! section 3.2):
//!
//! ```text
//! u(k) = u(k−1) + Kp·{ e(k) − e(k−1) + (τ/τi)·e(k) + (τd/τ)·[e(k) − 2e(k−1) + e(k−2)] }
//! ```
//!
//! with τ the sample period, τi the integral time and τd the derivative
//! time. Only e(k−1), e(k−2) and u(k−1) are kept between samples, which is
//! why the seed chose this form.
//!
//! # Fixed point
//!
//! Errors are signed counts (the card's 28-bit grating counters fit an
//! `i32`). The gains Kp, τ/τi and τd/τ are Q16.16 (`i32`, value × 2^16,
//! range ±32768 with a resolution of 1/65536). The braces are evaluated
//! exactly in Q16.16 (`i128`), multiplied by Kp and rounded to Q16.16; u is
//! kept in Q16.16 so that increments below one DAC code accumulate instead
//! of being lost.
//!
//! # DAC
//!
//! The card's DAC7744 is 16-bit with a bipolar ±10 V range; the output here
//! is a signed code, `i16` (−32768 = −10 V, 0 = 0 V, 32767 = +10 V − 1 LSB),
//! because an error of either sign drives the amplifier either way. The
//! DAC7744 itself takes straight binary, in which its bipolar mid-scale
//! 0x8000 is 0 V: [`dac_offset_binary`] converts. u is clamped to the DAC
//! range and the clamped value is what u(k−1) remembers, so the output
//! leaves a limit as soon as the error turns (no integral wind-up).

/// Q16.16 one.
pub const Q16_ONE: i32 = 1 << 16;

/// The three constants of the seed's formula, Q16.16.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PidGains {
    /// Kp.
    pub kp: i32,
    /// τ/τi (sample period over integral time).
    pub ti_ratio: i32,
    /// τd/τ (derivative time over sample period).
    pub td_ratio: i32,
}

impl PidGains {
    /// From Kp and the times τ, τi, τd (any one unit), rounded to Q16.16;
    /// τi = ∞ turns the integral term off, τd = 0 the derivative term.
    pub fn from_times(kp: f64, tau: f64, tau_i: f64, tau_d: f64) -> Self {
        let q = |x: f64| {
            let y = x * f64::from(Q16_ONE);
            // Round half away from zero; `as` saturates out-of-range values.
            (if y < 0.0 { y - 0.5 } else { y + 0.5 }) as i32
        };
        Self {
            kp: q(kp),
            ti_ratio: q(tau / tau_i),
            td_ratio: q(tau_d / tau),
        }
    }
}

/// Converts a signed DAC code to the DAC7744's straight binary (0x8000 =
/// mid-scale = 0 V in the bipolar range).
pub fn dac_offset_binary(code: i16) -> u16 {
    (code as u16) ^ 0x8000
}

/// The controller: gains, the last two errors and the last output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct IncrementalPid {
    gains: PidGains,
    /// e(k−1), e(k−2).
    e1: i32,
    e2: i32,
    /// u(k−1), Q16.16, within the DAC range.
    u: i64,
}

const U_MIN: i64 = (i16::MIN as i64) << 16;
const U_MAX: i64 = (i16::MAX as i64) << 16;

impl IncrementalPid {
    /// At rest: errors 0, output 0.
    pub fn new(gains: PidGains) -> Self {
        Self {
            gains,
            ..Self::default()
        }
    }

    pub fn gains(&self) -> PidGains {
        self.gains
    }

    /// Clears the errors and the output.
    pub fn reset(&mut self) {
        *self = Self::new(self.gains);
    }

    /// [e(k−1), e(k−2)].
    pub fn errors(&self) -> [i32; 2] {
        [self.e1, self.e2]
    }

    /// u(k−1) in Q16.16.
    pub fn output_q16(&self) -> i64 {
        self.u
    }

    /// u(k−1) rounded to a DAC code (half up).
    pub fn output(&self) -> i16 {
        ((self.u + (1 << 15)) >> 16).min(i64::from(i16::MAX)) as i16
    }

    /// One sample: takes e(k), returns u(k) as a DAC code.
    pub fn update(&mut self, e: i32) -> i16 {
        let (e0, e1, e2) = (i128::from(e), i128::from(self.e1), i128::from(self.e2));
        let g = self.gains;
        // The braces, Q16.16.
        let braces = ((e0 - e1) << 16)
            + i128::from(g.ti_ratio) * e0
            + i128::from(g.td_ratio) * (e0 - 2 * e1 + e2);
        // Kp × braces is Q32.32: round to Q16.16.
        let du = (i128::from(g.kp) * braces + (1 << 15)) >> 16;
        let u = (i128::from(self.u) + du).clamp(U_MIN.into(), U_MAX.into());
        self.u = u as i64;
        self.e2 = self.e1;
        self.e1 = e;
        self.output()
    }
}
