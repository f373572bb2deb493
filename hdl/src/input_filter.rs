//! Two-flop synchroniser and programmable digital filter for one input.

use rust_hdl::prelude::*;

/// Synchronises an asynchronous pin and accepts a new level only after it
/// has been seen on `setting`+1 consecutive clocks (docs/counter_bank.md,
/// "Input conditioning"). During reset the accepted level follows the
/// synchronised pin, so a resting input never looks like a change.
#[derive(LogicBlock, Default)]
pub struct InputFilter {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// The asynchronous pin.
    pub pin: Signal<In, Bit>,
    /// Filter setting F: a change must be seen on F+1 clocks (0 = off).
    pub setting: Signal<In, Bits<4>>,
    /// The accepted level.
    pub level: Signal<Out, Bit>,
    sync1: DFF<Bit>,
    sync2: DFF<Bit>,
    accepted: DFF<Bit>,
    count: DFF<Bits<4>>,
}

impl InputFilter {
    /// Every register, for comparison with the model.
    pub fn probe(&self) -> motionhdl_model::counter::InputFilter {
        motionhdl_model::counter::InputFilter {
            s1: self.sync1.q.val(),
            s2: self.sync2.q.val(),
            level: self.accepted.q.val(),
            cnt: self.count.q.val().to_u8(),
        }
    }
}

impl Logic for InputFilter {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, sync1, sync2, accepted, count);
        self.sync1.d.next = self.pin.val();
        self.sync2.d.next = self.sync1.q.val();
        if self.reset.val() {
            self.accepted.d.next = self.sync2.q.val();
            self.count.d.next = 0.into();
        } else if self.sync2.q.val() == self.accepted.q.val() {
            self.count.d.next = 0.into();
        } else if self.count.q.val() == self.setting.val() {
            self.accepted.d.next = self.sync2.q.val();
            self.count.d.next = 0.into();
        } else {
            self.count.d.next = self.count.q.val() + 1;
        }
        self.level.next = self.accepted.q.val();
    }
}
