//! 74LS153 dual 4-to-1 data selector, one port per chip pin.

use rust_hdl::prelude::*;

/// A 74LS153: two 4-to-1 multiplexers sharing select inputs A (LSB) and B
/// (MSB), each with an active-low strobe that forces its output low.
/// Purely combinational, like the chip.
#[derive(LogicBlock, Default)]
pub struct Ls153 {
    /// Select input A, least significant.
    pub a: Signal<In, Bit>,
    /// Select input B, most significant.
    pub b: Signal<In, Bit>,
    /// Strobe 1G̅: low enables section 1, high forces 1Y low.
    pub g1_n: Signal<In, Bit>,
    /// Strobe 2G̅: low enables section 2, high forces 2Y low.
    pub g2_n: Signal<In, Bit>,
    /// Data input 1C0, selected when B A = 00.
    pub c1_0: Signal<In, Bit>,
    /// Data input 1C1, selected when B A = 01.
    pub c1_1: Signal<In, Bit>,
    /// Data input 1C2, selected when B A = 10.
    pub c1_2: Signal<In, Bit>,
    /// Data input 1C3, selected when B A = 11.
    pub c1_3: Signal<In, Bit>,
    /// Data input 2C0, selected when B A = 00.
    pub c2_0: Signal<In, Bit>,
    /// Data input 2C1, selected when B A = 01.
    pub c2_1: Signal<In, Bit>,
    /// Data input 2C2, selected when B A = 10.
    pub c2_2: Signal<In, Bit>,
    /// Data input 2C3, selected when B A = 11.
    pub c2_3: Signal<In, Bit>,
    /// Output 1Y.
    pub y1: Signal<Out, Bit>,
    /// Output 2Y.
    pub y2: Signal<Out, Bit>,
}

impl Logic for Ls153 {
    #[hdl_gen]
    fn update(&mut self) {
        if self.b.val() {
            if self.a.val() {
                self.y1.next = self.c1_3.val() & !self.g1_n.val();
                self.y2.next = self.c2_3.val() & !self.g2_n.val();
            } else {
                self.y1.next = self.c1_2.val() & !self.g1_n.val();
                self.y2.next = self.c2_2.val() & !self.g2_n.val();
            }
        } else if self.a.val() {
            self.y1.next = self.c1_1.val() & !self.g1_n.val();
            self.y2.next = self.c2_1.val() & !self.g2_n.val();
        } else {
            self.y1.next = self.c1_0.val() & !self.g1_n.val();
            self.y2.next = self.c2_0.val() & !self.g2_n.val();
        }
    }
}
