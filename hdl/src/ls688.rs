//! 74LS688 8-bit identity comparator.

use rust_hdl::prelude::*;

/// A 74LS688: `p_eq_q_n` (pin P=Q̅) is low exactly when `g_n` is low and
/// P0..P7 equal Q0..Q7. Purely combinational, like the chip. On an ISA card:
/// P = SA9..SA2, Q = the base-address switches, G̅ = AEN.
#[derive(LogicBlock, Default)]
pub struct Ls688 {
    /// P0..P7 (bit i = pin Pi).
    pub p: Signal<In, Bits<8>>,
    /// Q0..Q7 (bit i = pin Qi).
    pub q: Signal<In, Bits<8>>,
    /// Enable G̅, active low.
    pub g_n: Signal<In, Bit>,
    /// Output P=Q̅, active low.
    pub p_eq_q_n: Signal<Out, Bit>,
}

impl Logic for Ls688 {
    #[hdl_gen]
    fn update(&mut self) {
        self.p_eq_q_n.next = !((self.p.val() == self.q.val()) & !self.g_n.val());
    }
}
