//! What sits outside the FPGA on the servo card's loop: a DAC7744 on the
//! DAC pins, a current amplifier driving a linear motor (a mass with
//! viscous friction and a force constant) and a grating ruler whose
//! quadrature output feeds the counter bank. Every parameter is stated
//! here and in docs/servo_loop.md.

use motionhdl_model::motion_controller::TopOutputs;
use motionhdl_model::pulse_generator::quadrature;
use motionhdl_model::servo_dac::SAFE_CODE;

/// DAC full scale: ±10 V (the DAC7744's bipolar range).
pub const DAC_FULL_SCALE_V: f64 = 10.0;
/// Amplifier transconductance (current mode), A per V.
pub const AMPLIFIER_A_PER_V: f64 = 1.0;
/// Linear motor force constant, N per A.
pub const FORCE_N_PER_A: f64 = 10.0;
/// Moving mass (slide and load), kg.
pub const MASS_KG: f64 = 0.5;
/// Viscous friction, N per (m/s): the slide coasts to rest with a time
/// constant of MASS_KG / FRICTION = 10 ms.
pub const FRICTION_N_S_PER_M: f64 = 50.0;
/// Grating ruler resolution: one count (one quadrature state, ×4 decoding
/// of a 4 µm signal period) per µm.
pub const RULER_M_PER_COUNT: f64 = 1e-6;

/// A DAC7744 as its pins drive it: CS's rise latches the data into the
/// addressed channel's input register, LOADDACS's rise moves all four input
/// registers to the outputs (data sheet Table I).
#[derive(Clone, Copy, Debug)]
pub struct Dac7744 {
    input: [u16; 4],
    /// The codes the four outputs hold.
    pub output: [u16; 4],
    last: Option<(u16, u8, bool, bool)>,
}

impl Default for Dac7744 {
    fn default() -> Self {
        Self {
            input: [SAFE_CODE as u16; 4],
            output: [SAFE_CODE as u16; 4],
            last: None,
        }
    }
}

impl Dac7744 {
    /// The pins after an edge.
    pub fn observe(&mut self, o: &TopOutputs) {
        if let Some((data, addr, cs_n, ldac_n)) = self.last {
            if !cs_n && o.dac_cs_n {
                self.input[usize::from(addr & 3)] = data;
            }
            if !ldac_n && o.dac_ldac_n {
                self.output = self.input;
            }
        }
        self.last = Some((o.dac_data, o.dac_addr, o.dac_cs_n, o.dac_ldac_n));
    }

    /// Output `channel`'s voltage.
    pub fn volts(&self, channel: usize) -> f64 {
        code_volts(self.output[channel])
    }
}

/// The voltage of a DAC code (straight binary, 0x8000 = 0 V).
pub fn code_volts(code: u16) -> f64 {
    (f64::from(code) - f64::from(SAFE_CODE as u16)) * DAC_FULL_SCALE_V / 32768.0
}

/// One axis: the motor's slide and the ruler on it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Axis {
    /// Slide position, m, and velocity, m/s.
    pub position: f64,
    pub velocity: f64,
    /// The count the ruler's output shows: it follows the slide one state
    /// per clock at most, as a ruler's interpolator output does.
    pub ruler: i64,
}

impl Axis {
    /// `dt` seconds with `volts` at the amplifier's input (semi-implicit
    /// Euler), then the ruler one state toward the slide.
    pub fn advance(&mut self, volts: f64, dt: f64) {
        let force = FORCE_N_PER_A * AMPLIFIER_A_PER_V * volts - FRICTION_N_S_PER_M * self.velocity;
        self.velocity += force / MASS_KG * dt;
        self.position += self.velocity * dt;
        let target = (self.position / RULER_M_PER_COUNT).floor() as i64;
        self.ruler += (target - self.ruler).signum();
    }

    /// The ruler's A and B.
    pub fn quadrature(&self) -> (bool, bool) {
        quadrature(self.ruler as u32)
    }

    /// The slide's position in ruler counts (not rounded).
    pub fn counts(&self) -> f64 {
        self.position / RULER_M_PER_COUNT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slide_coasts_with_the_stated_time_constant() {
        let mut a = Axis {
            velocity: 0.1,
            ..Default::default()
        };
        let tau = MASS_KG / FRICTION_N_S_PER_M;
        let dt = 20e-9;
        for _ in 0..(tau / dt) as usize {
            a.advance(0.0, dt);
        }
        // e^-1 of the speed after one time constant; the distance v0·τ(1 - 1/e).
        assert!((a.velocity / 0.1 - (-1.0f64).exp()).abs() < 1e-4, "{a:?}");
        let want = 0.1 * tau * (1.0 - (-1.0f64).exp());
        assert!((a.position - want).abs() < 1e-6, "{a:?}");
        assert_eq!(a.ruler, (a.position / RULER_M_PER_COUNT).floor() as i64);
    }

    #[test]
    fn full_scale_drives_the_terminal_speed() {
        let mut d = Dac7744::default();
        assert_eq!(d.volts(0), 0.0);
        d.output[0] = 0xFFFF;
        assert!((d.volts(0) - (10.0 - 10.0 / 32768.0)).abs() < 1e-12);
        // 10 V: 100 N against 50 N·s/m → 2 m/s.
        let mut a = Axis::default();
        for _ in 0..10_000 {
            a.advance(10.0, 10e-6);
        }
        assert!((a.velocity - 2.0).abs() < 1e-3, "{a:?}");
    }
}
