//! Registered step decision of a counter channel: quadrature ×4/×2/×1, pulse+direction
//! or CW/CCW, from the previous and current accepted levels of A and B.

use motionhdl_spec::regmap;
use rust_hdl::prelude::*;

/// The up/down decision for one accepted sample (docs/counter_bank.md,
/// "Counting"), registered: `up_q`/`down_q` are flip-flops, so nothing in
/// the parent depends combinationally on this block's inputs (no false
/// combinational loop through the flattened Verilog). Reserved modes never
/// count. Illegal-transition detection stays with the parent's error logic.
#[derive(LogicBlock)]
pub struct StepDecoder {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Register "no step" this clock (reset, or a LOAD's first edge).
    pub hold: Signal<In, Bit>,
    /// Accepted level of A now.
    pub a: Signal<In, Bit>,
    /// Accepted level of B now.
    pub b: Signal<In, Bit>,
    /// Accepted level of A one clock earlier.
    pub a_prev: Signal<In, Bit>,
    /// Accepted level of B one clock earlier.
    pub b_prev: Signal<In, Bit>,
    /// CTRL.MODE.
    pub mode: Signal<In, Bits<3>>,
    /// CTRL.REVERSE: swap up and down.
    pub reverse: Signal<In, Bit>,
    /// Count up at the next edge.
    pub up_q: Signal<Out, Bit>,
    /// Count down at the next edge.
    pub down_q: Signal<Out, Bit>,
    up_reg: DFF<Bit>,
    down_reg: DFF<Bit>,
    mode_x4: Constant<Bits<3>>,
    mode_x2: Constant<Bits<3>>,
    mode_x1: Constant<Bits<3>>,
    mode_pulse_dir: Constant<Bits<3>>,
    mode_cw_ccw: Constant<Bits<3>>,
    changed_a: Signal<Local, Bit>,
    changed_b: Signal<Local, Bit>,
    a_ne_b: Signal<Local, Bit>,
    rise_a: Signal<Local, Bit>,
    rise_b: Signal<Local, Bit>,
    forward: Signal<Local, Bit>,
    backward: Signal<Local, Bit>,
}

impl Default for StepDecoder {
    fn default() -> Self {
        let k3 = |v: u32| Constant::new((v as u64).into());
        Self {
            clock: Default::default(),
            hold: Default::default(),
            a: Default::default(),
            b: Default::default(),
            a_prev: Default::default(),
            b_prev: Default::default(),
            mode: Default::default(),
            reverse: Default::default(),
            up_q: Default::default(),
            down_q: Default::default(),
            up_reg: Default::default(),
            down_reg: Default::default(),
            mode_x4: k3(regmap::mode::X4),
            mode_x2: k3(regmap::mode::X2),
            mode_x1: k3(regmap::mode::X1),
            mode_pulse_dir: k3(regmap::mode::PULSE_DIR),
            mode_cw_ccw: k3(regmap::mode::CW_CCW),
            changed_a: Default::default(),
            changed_b: Default::default(),
            a_ne_b: Default::default(),
            rise_a: Default::default(),
            rise_b: Default::default(),
            forward: Default::default(),
            backward: Default::default(),
        }
    }
}

impl Logic for StepDecoder {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, up_reg, down_reg);
        self.changed_a.next = self.a.val() ^ self.a_prev.val();
        self.changed_b.next = self.b.val() ^ self.b_prev.val();
        self.a_ne_b.next = self.a.val() ^ self.b.val();
        self.rise_a.next = self.a.val() & !self.a_prev.val();
        self.rise_b.next = self.b.val() & !self.b_prev.val();
        self.forward.next = false;
        self.backward.next = false;
        if self.mode.val() == self.mode_x4.val() {
            self.forward.next = (self.changed_a.val() & !self.changed_b.val() & self.a_ne_b.val())
                | (self.changed_b.val() & !self.changed_a.val() & !self.a_ne_b.val());
            self.backward.next =
                (self.changed_a.val() & !self.changed_b.val() & !self.a_ne_b.val())
                    | (self.changed_b.val() & !self.changed_a.val() & self.a_ne_b.val());
        }
        if self.mode.val() == self.mode_x2.val() {
            self.forward.next = self.changed_a.val() & !self.changed_b.val() & self.a_ne_b.val();
            self.backward.next = self.changed_a.val() & !self.changed_b.val() & !self.a_ne_b.val();
        }
        if self.mode.val() == self.mode_x1.val() {
            self.forward.next =
                !self.a_prev.val() & !self.b_prev.val() & self.a.val() & !self.b.val();
            self.backward.next =
                self.a_prev.val() & !self.b_prev.val() & !self.a.val() & !self.b.val();
        }
        if self.mode.val() == self.mode_pulse_dir.val() {
            self.forward.next = self.rise_a.val() & !self.b.val();
            self.backward.next = self.rise_a.val() & self.b.val();
        }
        if self.mode.val() == self.mode_cw_ccw.val() {
            self.forward.next = self.rise_a.val() & !self.rise_b.val();
            self.backward.next = self.rise_b.val() & !self.rise_a.val();
        }
        if self.reverse.val() {
            self.up_reg.d.next = self.backward.val();
            self.down_reg.d.next = self.forward.val();
        } else {
            self.up_reg.d.next = self.forward.val();
            self.down_reg.d.next = self.backward.val();
        }
        if self.hold.val() {
            self.up_reg.d.next = false;
            self.down_reg.d.next = false;
        }
        self.up_q.next = self.up_reg.q.val();
        self.down_q.next = self.down_reg.q.val();
    }
}
