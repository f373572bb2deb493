//! The 74LS688 8-bit identity comparator, modelled pin for pin.
//!
//! Inputs P0..P7 and Q0..Q7 and an active-low enable G̅; one active-low
//! output P=Q̅, low exactly when G̅ is low and every Pi equals Qi. On an ISA
//! card P = SA9..SA2, Q = the base-address switches and G̅ = AEN, so DMA
//! cycles (AEN high) never select the card.

use bitvec::prelude::*;

/// Every input pin of the chip.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ls688Inputs {
    /// P0..P7, bit i = pin Pi.
    pub p: u8,
    /// Q0..Q7, bit i = pin Qi.
    pub q: u8,
    /// Enable G̅, active low.
    pub g_n: bool,
}

/// Number of input pins: P0..P7, Q0..Q7 and G̅.
pub const INPUT_PINS: u32 = 17;

impl Ls688Inputs {
    /// Unpacks a 17-bit word, LSB first: P0..P7, Q0..Q7, G̅. Used to
    /// enumerate every input combination.
    pub fn from_word(word: u32) -> Self {
        let bits = word.view_bits::<Lsb0>();
        Self {
            p: bits[0..8].load::<u8>(),
            q: bits[8..16].load::<u8>(),
            g_n: bits[16],
        }
    }

    /// The inverse of [`Ls688Inputs::from_word`].
    pub fn to_word(&self) -> u32 {
        let mut word = 0u32;
        let bits = word.view_bits_mut::<Lsb0>();
        bits[0..8].store::<u8>(self.p);
        bits[8..16].store::<u8>(self.q);
        bits.set(16, self.g_n);
        word
    }
}

/// The output P=Q̅ from the chip's logic diagram: one XNOR per bit pair,
/// then a 9-input NAND with the inverted enable (so high when any pair
/// differs or G̅ is high).
pub fn ls688(inputs: &Ls688Inputs) -> bool {
    let p = inputs.p.view_bits::<Lsb0>();
    let q = inputs.q.view_bits::<Lsb0>();
    let all_equal = p.iter().zip(q.iter()).all(|(pi, qi)| *pi == *qi);
    !all_equal || inputs.g_n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn word_round_trip_covers_every_input() {
        let mut n = 0u32;
        for w in 0..(1u32 << INPUT_PINS) {
            assert_eq!(Ls688Inputs::from_word(w).to_word(), w);
            n += 1;
        }
        assert_eq!(n, 131_072);
    }

    #[test]
    fn datasheet_function_table() {
        // SN74LS688 function table: P,Q | G̅ | P=Q̅.
        let rows = [
            (0x5a, 0x5a, false, false), // P = Q, enabled: L
            (0x5a, 0x5b, false, true),  // P > Q: H
            (0x5a, 0x59, false, true),  // P < Q: H
            (0x5a, 0x5a, true, true),   // disabled: H
            (0x00, 0x80, false, true),  // only P7/Q7 differ
        ];
        for (p, q, g_n, out) in rows {
            assert_eq!(
                ls688(&Ls688Inputs { p, q, g_n }),
                out,
                "P={p:#x} Q={q:#x} G={g_n}"
            );
        }
    }

    #[test]
    fn output_is_low_only_for_equal_enabled_inputs() {
        let mut low = 0;
        for w in 0..(1u32 << INPUT_PINS) {
            let i = Ls688Inputs::from_word(w);
            if !ls688(&i) {
                assert!(i.p == i.q && !i.g_n, "inputs {i:?}");
                low += 1;
            }
        }
        assert_eq!(low, 256, "one match per P value");
    }
}
