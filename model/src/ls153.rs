//! The 74LS153 dual 4-to-1 data selector/multiplexer, modelled pin for pin.
//!
//! Two multiplexers share the select inputs A (LSB) and B (MSB). Each has four
//! data inputs nC0..nC3 and an active-low strobe nG̅: with the strobe high
//! (inactive) the output nY is forced low, whatever the data.

use bitvec::prelude::*;

/// Data inputs of one section, `c[i]` = pin nCi.
pub type DataInputs = BitArr!(for 4, in u8, Lsb0);

/// Every input pin of the chip.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ls153Inputs {
    /// Select input A (least significant).
    pub a: bool,
    /// Select input B (most significant).
    pub b: bool,
    /// Strobe 1G̅, active low.
    pub g1_n: bool,
    /// Strobe 2G̅, active low.
    pub g2_n: bool,
    /// Data inputs 1C0..1C3.
    pub c1: DataInputs,
    /// Data inputs 2C0..2C3.
    pub c2: DataInputs,
}

/// The two outputs 1Y and 2Y.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ls153Outputs {
    pub y1: bool,
    pub y2: bool,
}

/// Number of input pins: A, B, 1G̅, 2G̅ and eight data inputs.
pub const INPUT_PINS: u32 = 12;

impl Ls153Inputs {
    /// Unpacks a 12-bit word, LSB first: A, B, 1G̅, 2G̅, 1C0..1C3, 2C0..2C3.
    /// Used to enumerate every input combination.
    pub fn from_word(word: u16) -> Self {
        let bits = word.view_bits::<Lsb0>();
        let mut c1 = DataInputs::ZERO;
        let mut c2 = DataInputs::ZERO;
        c1[..4].store::<u8>(bits[4..8].load::<u8>());
        c2[..4].store::<u8>(bits[8..12].load::<u8>());
        Self {
            a: bits[0],
            b: bits[1],
            g1_n: bits[2],
            g2_n: bits[3],
            c1,
            c2,
        }
    }

    /// The inverse of [`Ls153Inputs::from_word`].
    pub fn to_word(&self) -> u16 {
        let mut word = 0u16;
        let bits = word.view_bits_mut::<Lsb0>();
        bits.set(0, self.a);
        bits.set(1, self.b);
        bits.set(2, self.g1_n);
        bits.set(3, self.g2_n);
        bits[4..8].store::<u8>(self.c1[..4].load::<u8>());
        bits[8..12].store::<u8>(self.c2[..4].load::<u8>());
        word
    }

    /// The selected data input index, 0..=3.
    pub fn select(&self) -> usize {
        (usize::from(self.b) << 1) | usize::from(self.a)
    }
}

/// The chip's function table.
pub fn ls153(inputs: &Ls153Inputs) -> Ls153Outputs {
    let sel = inputs.select();
    Ls153Outputs {
        y1: !inputs.g1_n && inputs.c1[sel],
        y2: !inputs.g2_n && inputs.c2[sel],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn word_round_trip_covers_every_input() {
        let mut n = 0;
        for w in 0..(1u16 << INPUT_PINS) {
            assert_eq!(Ls153Inputs::from_word(w).to_word(), w);
            n += 1;
        }
        assert_eq!(n, 4096);
    }

    #[test]
    fn strobe_high_forces_output_low() {
        for w in 0..(1u16 << INPUT_PINS) {
            let i = Ls153Inputs::from_word(w);
            let o = ls153(&i);
            if i.g1_n {
                assert!(!o.y1, "inputs {i:?}");
            }
            if i.g2_n {
                assert!(!o.y2, "inputs {i:?}");
            }
        }
    }

    #[test]
    fn datasheet_function_table() {
        // SN74LS153 function table, section 1: B A | C0 C1 C2 C3 | G̅ | Y.
        let c = |bits: u8| {
            let mut d = DataInputs::ZERO;
            d[..4].store(bits);
            d
        };
        let rows: [(bool, bool, u8, bool, bool); 9] = [
            (false, false, 0b0000, true, false), // strobe high: L
            (false, false, 0b0000, false, false),
            (false, false, 0b0001, false, true),
            (false, true, 0b0000, false, false),
            (false, true, 0b0010, false, true),
            (true, false, 0b0000, false, false),
            (true, false, 0b0100, false, true),
            (true, true, 0b0000, false, false),
            (true, true, 0b1000, false, true),
        ];
        for (b, a, data, g_n, y) in rows {
            let i = Ls153Inputs {
                a,
                b,
                g1_n: g_n,
                g2_n: true,
                c1: c(data),
                c2: DataInputs::ZERO,
            };
            assert_eq!(ls153(&i).y1, y, "B={b} A={a} C={data:04b} G={g_n}");
        }
    }
}
