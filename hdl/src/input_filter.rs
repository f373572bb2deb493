//! Two-flop synchroniser and programmable digital filter for one input.

use rust_hdl::prelude::*;

/// Synchronises an asynchronous pin and accepts a new level only after it
/// has been seen on `setting`+1 consecutive clocks (docs/counter_bank.md,
/// "Input conditioning"). During reset the accepted level follows the
/// synchronised pin, so a resting input never looks like a change.
///
/// The counter counts down: it is loaded with F while the sample equals the
/// accepted level and the change is accepted when it reaches 0, so the
/// accept test does not read CTRL, which only feeds the counter's load
/// value. A registered `count_nonzero` flag beside the counter makes the
/// accept test a single LUT (not a register of the specification).
#[derive(LogicBlock)]
pub struct InputFilter {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// The asynchronous pin.
    pub pin: Signal<In, Bit>,
    /// Filter setting F: a change must be seen on F+1 clocks (0 = off); read
    /// on the clocks where the sample equals the accepted level.
    pub setting: Signal<In, Bits<4>>,
    /// The accepted level.
    pub level: Signal<Out, Bit>,
    sync1: DFF<Bit>,
    sync2: DFF<Bit>,
    accepted: DFF<Bit>,
    count: DFF<Bits<4>>,
    count_nonzero: DFF<Bit>,
    one: Constant<Bits<4>>,
    // 0 in a build without the filter: the count is held at 0, so a change
    // is accepted the clock after `sync2` shows it and synthesis drops the
    // counter (it cannot prove by itself that the count stays 0).
    filtering: Constant<Bit>,
}

impl Default for InputFilter {
    fn default() -> Self {
        Self::with_filtering(true)
    }
}

impl InputFilter {
    /// A filter (`filtering`) or a plain synchroniser with the same latency.
    pub fn with_filtering(filtering: bool) -> Self {
        Self {
            clock: Default::default(),
            reset: Default::default(),
            pin: Default::default(),
            setting: Default::default(),
            level: Default::default(),
            sync1: Default::default(),
            sync2: Default::default(),
            accepted: Default::default(),
            count: Default::default(),
            count_nonzero: Default::default(),
            one: Constant::new(1u64.into()),
            filtering: Constant::new(filtering),
        }
    }

    /// Contract: the `count_nonzero` flag describes the counter.
    pub fn consistent(&self) -> bool {
        self.count_nonzero.q.val() == self.count.q.val().any()
    }

    /// Every register, for comparison with the model.
    pub fn probe(&self) -> crate::probe::FilterRegisters {
        crate::probe::FilterRegisters {
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
        dff_setup!(self, clock, sync1, sync2, accepted, count, count_nonzero);
        self.sync1.d.next = self.pin.val();
        self.sync2.d.next = self.sync1.q.val();
        if self.reset.val() {
            self.accepted.d.next = self.sync2.q.val();
            self.count.d.next = 0.into();
            self.count_nonzero.d.next = false;
        } else if self.sync2.q.val() == self.accepted.q.val() {
            self.count.d.next = self.setting.val();
            self.count_nonzero.d.next = self.setting.val().any();
        } else if !self.count_nonzero.q.val() {
            self.accepted.d.next = self.sync2.q.val();
            self.count.d.next = self.setting.val();
            self.count_nonzero.d.next = self.setting.val().any();
        } else {
            self.count.d.next = self.count.q.val() - 1;
            self.count_nonzero.d.next = self.count.q.val() != self.one.val();
        }
        if !self.filtering.val() {
            self.count.d.next = 0.into();
            self.count_nonzero.d.next = false;
        }
        self.level.next = self.accepted.q.val();
    }
}
