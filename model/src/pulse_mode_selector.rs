//! The command-pulse mode selector of the dual-CPU seed card (its Table 3).
//!
//! Inputs: S1 = pulse (the CPU's PWM output), S2 = direction, K = mode.
//! K = 0 selects pulse+direction (F1 = S1, F2 = S2); K = 1 selects CW/CCW
//! (F1 = ¬S2·S1 carries forward pulses, F2 = S2·S1 reverse pulses).
//! F1 is the A-phase output, F2 the B-phase output.
//!
//! Three independent forms are given and cross-checked: the seed's truth
//! table as data, its sum-of-minterms equations (1) and (2), and the one-chip
//! 74LS153 wiring the seed derives by Karnaugh-map reduction.

use crate::ls153::{ls153, DataInputs, Ls153Inputs};

/// Command-pulse mode, the K input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PulseMode {
    /// K = 0: pulse on F1, direction level on F2.
    PulseDirection,
    /// K = 1: forward pulses on F1 (CW), reverse pulses on F2 (CCW).
    CwCcw,
}

impl PulseMode {
    pub fn k(self) -> bool {
        self == PulseMode::CwCcw
    }
}

/// One row of the truth table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Row {
    pub k: bool,
    pub s2: bool,
    pub s1: bool,
    pub f1: bool,
    pub f2: bool,
}

const fn row(k: u8, s2: u8, s1: u8, f1: u8, f2: u8) -> Row {
    Row {
        k: k != 0,
        s2: s2 != 0,
        s1: s1 != 0,
        f1: f1 != 0,
        f2: f2 != 0,
    }
}

/// The seed's Table 3, in minterm order (K S2 S1 = 000 .. 111).
pub const TRUTH_TABLE: [Row; 8] = [
    row(0, 0, 0, 0, 0),
    row(0, 0, 1, 1, 0),
    row(0, 1, 0, 0, 1),
    row(0, 1, 1, 1, 1),
    row(1, 0, 0, 0, 0),
    row(1, 0, 1, 1, 0),
    row(1, 1, 0, 0, 0),
    row(1, 1, 1, 0, 1),
];

/// Equation (1): F1 = Σm(1,3,5) over (K,S2,S1).
pub const F1_MINTERMS: [u8; 3] = [1, 3, 5];
/// Equation (2): F2 = Σm(2,3,7) over (K,S2,S1).
pub const F2_MINTERMS: [u8; 3] = [2, 3, 7];

/// Minterm index of an input combination: K is the MSB, S1 the LSB.
pub fn minterm(k: bool, s2: bool, s1: bool) -> u8 {
    (u8::from(k) << 2) | (u8::from(s2) << 1) | u8::from(s1)
}

/// Evaluates a sum of minterms.
pub fn sum_of_minterms(minterms: &[u8], k: bool, s2: bool, s1: bool) -> bool {
    minterms.contains(&minterm(k, s2, s1))
}

/// Looks the inputs up in [`TRUTH_TABLE`]; returns (F1, F2).
pub fn from_truth_table(k: bool, s2: bool, s1: bool) -> (bool, bool) {
    let r = TRUTH_TABLE[usize::from(minterm(k, s2, s1))];
    (r.f1, r.f2)
}

/// Evaluates equations (1) and (2); returns (F1, F2).
pub fn from_minterms(k: bool, s2: bool, s1: bool) -> (bool, bool) {
    (
        sum_of_minterms(&F1_MINTERMS, k, s2, s1),
        sum_of_minterms(&F2_MINTERMS, k, s2, s1),
    )
}

/// What a 74LS153 data input is tied to in the one-chip realisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tie {
    /// Driven by the pulse input S1.
    S1,
    /// Tied to ground.
    Low,
    /// Tied to VCC.
    High,
}

impl Tie {
    pub fn level(self, s1: bool) -> bool {
        match self {
            Tie::S1 => s1,
            Tie::Low => false,
            Tie::High => true,
        }
    }
}

/// The Karnaugh-map reduction: select B = K, A = S2, both strobes tied low,
/// and each data input tied to S1, 0 or 1. `C1[i]` / `C2[i]` is the input
/// selected when (K,S2) = i.
///
/// Section 1 (F1): F1 = S1 except when K=1, S2=1.
pub const WIRING_C1: [Tie; 4] = [Tie::S1, Tie::S1, Tie::S1, Tie::Low];
/// Section 2 (F2): F2 = S2 when K=0; F2 = S1 when K=1, S2=1.
pub const WIRING_C2: [Tie; 4] = [Tie::Low, Tie::High, Tie::Low, Tie::S1];

/// The pin levels the wiring applies to the chip for given K, S2, S1.
pub fn chip_inputs(k: bool, s2: bool, s1: bool) -> Ls153Inputs {
    let mut c1 = DataInputs::ZERO;
    let mut c2 = DataInputs::ZERO;
    for i in 0..4 {
        c1.set(i, WIRING_C1[i].level(s1));
        c2.set(i, WIRING_C2[i].level(s1));
    }
    Ls153Inputs {
        a: s2,
        b: k,
        g1_n: false,
        g2_n: false,
        c1,
        c2,
    }
}

/// Evaluates the one-chip realisation; returns (F1, F2).
pub fn from_chip(k: bool, s2: bool, s1: bool) -> (bool, bool) {
    let y = ls153(&chip_inputs(k, s2, s1));
    (y.y1, y.y2)
}

/// The reference used by the testbench: the truth table itself.
pub fn select(mode: PulseMode, s2: bool, s1: bool) -> (bool, bool) {
    from_truth_table(mode.k(), s2, s1)
}

/// Cycle model of the registered variant: outputs are the selector's value
/// at the previous clock edge, zero after reset.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegisteredSelector {
    f1: bool,
    f2: bool,
}

impl RegisteredSelector {
    /// Outputs as seen during the current cycle.
    pub fn outputs(&self) -> (bool, bool) {
        (self.f1, self.f2)
    }
    /// Applies one rising clock edge with the given inputs.
    pub fn clock(&mut self, reset: bool, k: bool, s2: bool, s1: bool) {
        let (f1, f2) = if reset {
            (false, false)
        } else {
            from_truth_table(k, s2, s1)
        };
        self.f1 = f1;
        self.f2 = f2;
    }
}

/// Rising edges in a sampled waveform.
pub fn rising_edges(samples: impl IntoIterator<Item = bool>) -> usize {
    let mut prev = false;
    let mut n = 0;
    for s in samples {
        if s && !prev {
            n += 1;
        }
        prev = s;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_inputs() -> impl Iterator<Item = (bool, bool, bool)> {
        (0u8..8).map(|m| (m & 4 != 0, m & 2 != 0, m & 1 != 0))
    }

    #[test]
    fn table_minterms_and_chip_agree_on_all_eight_inputs() {
        let mut covered = 0;
        for (k, s2, s1) in all_inputs() {
            let t = from_truth_table(k, s2, s1);
            assert_eq!(from_minterms(k, s2, s1), t, "K={k} S2={s2} S1={s1}");
            assert_eq!(from_chip(k, s2, s1), t, "K={k} S2={s2} S1={s1}");
            covered += 1;
        }
        assert_eq!(covered, 8);
    }

    #[test]
    fn minterms_are_derived_from_the_table() {
        let f1: Vec<u8> = TRUTH_TABLE
            .iter()
            .filter(|r| r.f1)
            .map(|r| minterm(r.k, r.s2, r.s1))
            .collect();
        let f2: Vec<u8> = TRUTH_TABLE
            .iter()
            .filter(|r| r.f2)
            .map(|r| minterm(r.k, r.s2, r.s1))
            .collect();
        assert_eq!(f1, F1_MINTERMS);
        assert_eq!(f2, F2_MINTERMS);
    }

    #[test]
    fn modes_mean_what_the_seed_says() {
        for (_, s2, s1) in all_inputs() {
            assert_eq!(select(PulseMode::PulseDirection, s2, s1), (s1, s2));
            assert_eq!(select(PulseMode::CwCcw, s2, s1), (!s2 && s1, s2 && s1));
        }
    }

    #[test]
    fn registered_variant_delays_by_one_clock_and_resets() {
        let mut r = RegisteredSelector::default();
        r.clock(false, false, true, true);
        assert_eq!(r.outputs(), (true, true));
        r.clock(true, false, true, true);
        assert_eq!(r.outputs(), (false, false));
    }

    /// The checks count steps on sampled pins with this: each low-to-high
    /// step, the first sample counting as one after a low.
    #[test]
    fn rising_edges_counts_each_low_to_high_step() {
        let cases: [(&[bool], usize); 6] = [
            (&[], 0),
            (&[true], 1),
            (&[true, true, true], 1),
            (&[false, false], 0),
            (&[false, true, true, false, true], 2),
            (&[true, false, true, false], 2),
        ];
        for (samples, edges) in cases {
            assert_eq!(rising_edges(samples.iter().copied()), edges, "{samples:?}");
        }
    }
}
