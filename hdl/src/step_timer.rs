//! The output timing state machine of a pulse generator: a signed queue of
//! commanded steps, emitted as S1/S2 with minimum step length, step space,
//! direction set-up and direction hold (docs/pulse_generator.md).

use rust_hdl::prelude::*;

/// `P`-bit signed queue (two's complement), `T`-bit timing inputs and
/// saturating timers. A step request the queue cannot take is refused
/// (`accept_up`/`accept_down` low): the NCO then holds, so no step is lost.
/// A step waits in the queue until every timing allows it.
#[derive(LogicBlock)]
pub struct StepTimer<const P: usize, const T: usize> {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Queue one step in the positive direction (only if `accept_up`).
    pub request_up: Signal<In, Bit>,
    /// Queue one step in the negative direction (only if `accept_down`).
    pub request_down: Signal<In, Bit>,
    /// S1 high for at least this many clocks (0 counts as 1).
    pub step_len: Signal<In, Bits<T>>,
    /// S1 low for at least this many clocks between steps.
    pub step_space: Signal<In, Bits<T>>,
    /// S2 stable for at least this many clocks before S1 rises.
    pub dir_setup: Signal<In, Bits<T>>,
    /// S1 low for at least this many clocks before S2 changes.
    pub dir_hold: Signal<In, Bits<T>>,
    /// S1, registered.
    pub step: Signal<Out, Bit>,
    /// S2, registered: 1 = negative direction.
    pub dir: Signal<Out, Bit>,
    /// A positive step rises at this edge (combinational).
    pub emit_up: Signal<Out, Bit>,
    /// A negative step rises at this edge (combinational).
    pub emit_down: Signal<Out, Bit>,
    /// The queue can take an up request this clock.
    pub accept_up: Signal<Out, Bit>,
    /// The queue can take a down request this clock.
    pub accept_down: Signal<Out, Bit>,
    /// Commanded minus emitted steps.
    pub pending: Signal<Out, Bits<P>>,
    pending_q: DFF<Bits<P>>,
    step_q: DFF<Bit>,
    dir_q: DFF<Bit>,
    t_step: DFF<Bits<T>>,
    t_dir: DFF<Bits<T>>,
    sign_mask: Constant<Bits<P>>,
    pending_max: Constant<Bits<P>>,
    pending_min: Constant<Bits<P>>,
    one: Constant<Bits<P>>,
    minus_one: Constant<Bits<P>>,
    two: Constant<Bits<P>>,
    minus_two: Constant<Bits<P>>,
    timer_one: Constant<Bits<T>>,
    timer_max: Constant<Bits<T>>,
    want_negative: Signal<Local, Bit>,
    emit: Signal<Local, Bit>,
    delta: Signal<Local, Bits<P>>,
}

impl<const P: usize, const T: usize> Default for StepTimer<P, T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const P: usize, const T: usize> StepTimer<P, T> {
    pub fn new() -> Self {
        assert!((3..=16).contains(&P), "P = {P} out of range 3..=16");
        assert!((1..=16).contains(&T), "T = {T} out of range 1..=16");
        let mask = (1u64 << P) - 1;
        let k = |v: u64| Constant::new((v & mask).into());
        let max = (1u64 << (P - 1)) - 1;
        Self {
            clock: Default::default(),
            reset: Default::default(),
            request_up: Default::default(),
            request_down: Default::default(),
            step_len: Default::default(),
            step_space: Default::default(),
            dir_setup: Default::default(),
            dir_hold: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            emit_up: Default::default(),
            emit_down: Default::default(),
            accept_up: Default::default(),
            accept_down: Default::default(),
            pending: Default::default(),
            pending_q: Default::default(),
            step_q: Default::default(),
            dir_q: Default::default(),
            t_step: Default::default(),
            t_dir: Default::default(),
            sign_mask: k(1 << (P - 1)),
            pending_max: k(max),
            pending_min: k(max.wrapping_neg()),
            one: k(1),
            minus_one: k(u64::MAX),
            two: k(2),
            minus_two: k(u64::MAX - 1),
            timer_one: Constant::new(1.into()),
            timer_max: Constant::new(((1u64 << T) - 1).into()),
            want_negative: Default::default(),
            emit: Default::default(),
            delta: Default::default(),
        }
    }

    /// Every register, for comparison with the model.
    pub fn probe(&self) -> crate::probe::StepTimerRegisters {
        let p = self.pending_q.q.val().index() as i64;
        let pending = if (p >> (P - 1)) & 1 == 1 {
            p - (1i64 << P)
        } else {
            p
        };
        crate::probe::StepTimerRegisters {
            pending: pending as i32,
            step: self.step_q.q.val(),
            dir: self.dir_q.q.val(),
            t_step: self.t_step.q.val().index() as u32,
            t_dir: self.t_dir.q.val().index() as u32,
        }
    }
}

impl<const P: usize, const T: usize> Logic for StepTimer<P, T> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, pending_q, step_q, dir_q, t_step, t_dir);
        self.want_negative.next = (self.pending_q.q.val() & self.sign_mask.val()).any();
        self.emit.next = !self.step_q.q.val()
            & self.pending_q.q.val().any()
            & (self.dir_q.q.val() == self.want_negative.val())
            & (self.t_step.q.val() >= self.step_space.val())
            & (self.t_dir.q.val() >= self.dir_setup.val());
        // Timers count clocks since their signal's last change, saturating.
        if self.t_step.q.val() != self.timer_max.val() {
            self.t_step.d.next = self.t_step.q.val() + self.timer_one.val();
        }
        if self.t_dir.q.val() != self.timer_max.val() {
            self.t_dir.d.next = self.t_dir.q.val() + self.timer_one.val();
        }
        if self.step_q.q.val() {
            if self.t_step.q.val() >= self.step_len.val() {
                self.step_q.d.next = false;
                self.t_step.d.next = self.timer_one.val();
            }
        } else if self.emit.val() {
            self.step_q.d.next = true;
            self.t_step.d.next = self.timer_one.val();
        } else if self.pending_q.q.val().any()
            & (self.dir_q.q.val() != self.want_negative.val())
            & (self.t_step.q.val() >= self.dir_hold.val())
        {
            self.dir_q.d.next = !self.dir_q.q.val();
            self.t_dir.d.next = self.timer_one.val();
        }
        // Commanded minus emitted, as one addend of one adder. An emitted
        // negative step (dir high) adds one.
        self.delta.next = 0.into();
        if self.emit.val() {
            if self.dir_q.q.val() {
                self.delta.next = self.one.val();
                if self.request_up.val() {
                    self.delta.next = self.two.val();
                }
                if self.request_down.val() {
                    self.delta.next = 0.into();
                }
            } else {
                self.delta.next = self.minus_one.val();
                if self.request_up.val() {
                    self.delta.next = 0.into();
                }
                if self.request_down.val() {
                    self.delta.next = self.minus_two.val();
                }
            }
        } else {
            if self.request_up.val() {
                self.delta.next = self.one.val();
            }
            if self.request_down.val() {
                self.delta.next = self.minus_one.val();
            }
        }
        self.pending_q.d.next = self.pending_q.q.val() + self.delta.val();
        if self.reset.val() {
            self.pending_q.d.next = 0.into();
            self.step_q.d.next = false;
            self.dir_q.d.next = false;
            self.t_step.d.next = self.timer_max.val();
            self.t_dir.d.next = self.timer_max.val();
        }
        self.step.next = self.step_q.q.val();
        self.dir.next = self.dir_q.q.val();
        self.emit_up.next = self.emit.val() & !self.dir_q.q.val();
        self.emit_down.next = self.emit.val() & self.dir_q.q.val();
        self.accept_up.next = self.pending_q.q.val() != self.pending_max.val();
        self.accept_down.next = self.pending_q.q.val() != self.pending_min.val();
        self.pending.next = self.pending_q.q.val();
    }
}
