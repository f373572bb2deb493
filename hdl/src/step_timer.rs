//! The output timing state machine of a pulse generator: a signed queue of
//! commanded steps, emitted as S1/S2 with minimum step length, step space,
//! direction set-up and direction hold (docs/pulse_generator.md).

use rust_hdl::prelude::*;

/// `P`-bit signed queue (two's complement), `T`-bit timing inputs and
/// saturating timers. A step request the queue cannot take must not be
/// made: `room_up`/`room_down` say a request decided now and arriving one
/// clock later still fits. A step waits in the queue until every timing
/// allows it. Every comparison is made a clock ahead into a flag
/// flip-flop, so the paths into the queue's adder start at flip-flops
/// (docs/pulse_generator.md).
#[derive(LogicBlock)]
pub struct StepTimer<const P: usize, const T: usize> {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Queue one step in the positive direction (the queue must be below
    /// its maximum).
    pub request_up: Signal<In, Bit>,
    /// Queue one step in the negative direction.
    pub request_down: Signal<In, Bit>,
    /// Empty the queue at this edge (the request and the leaving step go
    /// with it); no step starts and S2 does not turn. S1 already high
    /// falls after its length as usual.
    pub flush: Signal<In, Bit>,
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
    /// A positive step leaves the queue at this edge (S1 rose at the last).
    pub leave_up: Signal<Out, Bit>,
    /// A negative step leaves the queue at this edge.
    pub leave_down: Signal<Out, Bit>,
    /// The queue is at least two steps below its maximum.
    pub room_up: Signal<Out, Bit>,
    /// The queue is at least two steps above its minimum.
    pub room_down: Signal<Out, Bit>,
    /// Commanded minus emitted steps.
    pub pending: Signal<Out, Bits<P>>,
    pending_q: DFF<Bits<P>>,
    step_q: DFF<Bit>,
    dir_q: DFF<Bit>,
    t_step: DFF<Bits<T>>,
    t_dir: DFF<Bits<T>>,
    space_ok: DFF<Bit>,
    setup_ok: DFF<Bit>,
    len_ok: DFF<Bit>,
    hold_ok: DFF<Bit>,
    emitted: DFF<Bit>,
    nonzero: DFF<Bit>,
    sign_mask: Constant<Bits<P>>,
    pending_max: Constant<Bits<P>>,
    pending_max_less_one: Constant<Bits<P>>,
    pending_min: Constant<Bits<P>>,
    pending_min_plus_one: Constant<Bits<P>>,
    one: Constant<Bits<P>>,
    minus_one: Constant<Bits<P>>,
    two: Constant<Bits<P>>,
    minus_two: Constant<Bits<P>>,
    timer_one: Constant<Bits<T>>,
    timer_restart: Constant<Bits<T>>,
    timer_max: Constant<Bits<T>>,
    want_negative: Signal<Local, Bit>,
    pending_next: Signal<Local, Bits<P>>,
    emit: Signal<Local, Bit>,
    falls: Signal<Local, Bit>,
    turns: Signal<Local, Bit>,
    step_event: Signal<Local, Bit>,
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
        let timer_max = (1u64 << T) - 1;
        Self {
            clock: Default::default(),
            reset: Default::default(),
            request_up: Default::default(),
            request_down: Default::default(),
            flush: Default::default(),
            step_len: Default::default(),
            step_space: Default::default(),
            dir_setup: Default::default(),
            dir_hold: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            leave_up: Default::default(),
            leave_down: Default::default(),
            room_up: Default::default(),
            room_down: Default::default(),
            pending: Default::default(),
            pending_q: Default::default(),
            step_q: Default::default(),
            dir_q: Default::default(),
            t_step: Default::default(),
            t_dir: Default::default(),
            space_ok: Default::default(),
            setup_ok: Default::default(),
            len_ok: Default::default(),
            hold_ok: Default::default(),
            emitted: Default::default(),
            nonzero: Default::default(),
            sign_mask: k(1 << (P - 1)),
            pending_max: k(max),
            pending_max_less_one: k(max - 1),
            pending_min: k(max.wrapping_neg()),
            pending_min_plus_one: k((max - 1).wrapping_neg()),
            one: k(1),
            minus_one: k(u64::MAX),
            two: k(2),
            minus_two: k(u64::MAX - 1),
            timer_one: Constant::new(1.into()),
            // The timers hold their value of the next clock: 2 in the
            // first clock after a change (1 for a 1-bit timer).
            timer_restart: Constant::new(2u64.min(timer_max).into()),
            timer_max: Constant::new(timer_max.into()),
            want_negative: Default::default(),
            pending_next: Default::default(),
            emit: Default::default(),
            falls: Default::default(),
            turns: Default::default(),
            step_event: Default::default(),
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
            space_ok: self.space_ok.q.val(),
            setup_ok: self.setup_ok.q.val(),
            len_ok: self.len_ok.q.val(),
            hold_ok: self.hold_ok.q.val(),
            emitted: self.emitted.q.val(),
        }
    }
}

impl<const P: usize, const T: usize> Logic for StepTimer<P, T> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, pending_q, step_q, dir_q, t_step, t_dir, space_ok, setup_ok, len_ok,
            hold_ok, emitted, nonzero
        );
        self.want_negative.next = (self.pending_q.q.val() & self.sign_mask.val()).any();
        self.emit.next = !self.flush.val()
            & !self.step_q.q.val()
            & self.nonzero.q.val()
            & (self.dir_q.q.val() == self.want_negative.val())
            & self.space_ok.q.val()
            & self.setup_ok.q.val();
        self.falls.next = self.step_q.q.val() & self.len_ok.q.val();
        // (A step can only start with S2 already right, so no `!emit`.)
        self.turns.next = !self.flush.val()
            & !self.step_q.q.val()
            & self.nonzero.q.val()
            & (self.dir_q.q.val() != self.want_negative.val())
            & self.hold_ok.q.val();
        self.step_event.next = self.falls.val() | self.emit.val();
        // S1 and S2.
        self.step_q.d.next = self.step_q.q.val() ^ self.step_event.val();
        self.dir_q.d.next = self.dir_q.q.val() ^ self.turns.val();
        self.emitted.d.next = self.emit.val();
        // Timers hold their next clock's value, saturating; each flag is
        // the comparison the next clock needs, against this clock's
        // timing: one carry chain from flip-flops, then a select.
        if self.t_step.q.val() != self.timer_max.val() {
            self.t_step.d.next = self.t_step.q.val() + self.timer_one.val();
        }
        if self.t_dir.q.val() != self.timer_max.val() {
            self.t_dir.d.next = self.t_dir.q.val() + self.timer_one.val();
        }
        self.space_ok.d.next = self.t_step.q.val() >= self.step_space.val();
        self.len_ok.d.next = self.t_step.q.val() >= self.step_len.val();
        self.hold_ok.d.next = self.t_step.q.val() >= self.dir_hold.val();
        self.setup_ok.d.next = self.t_dir.q.val() >= self.dir_setup.val();
        if self.step_event.val() {
            self.t_step.d.next = self.timer_restart.val();
            self.space_ok.d.next = self.step_space.val() <= self.timer_one.val();
            self.len_ok.d.next = self.step_len.val() <= self.timer_one.val();
            self.hold_ok.d.next = self.dir_hold.val() <= self.timer_one.val();
        }
        if self.turns.val() {
            self.t_dir.d.next = self.timer_restart.val();
            self.setup_ok.d.next = self.dir_setup.val() <= self.timer_one.val();
        }
        // Commanded minus emitted, as one addend of one adder whose
        // inputs are all flip-flops: the requester's command register and
        // the step S1 started at the last edge.
        self.delta.next = 0.into();
        if self.emitted.q.val() {
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
        self.pending_next.next = self.pending_q.q.val() + self.delta.val();
        if self.flush.val() {
            self.pending_next.next = 0.into();
        }
        if self.reset.val() {
            self.pending_next.next = 0.into();
            self.step_q.d.next = false;
            self.dir_q.d.next = false;
            self.emitted.d.next = false;
            self.t_step.d.next = self.timer_max.val();
            self.t_dir.d.next = self.timer_max.val();
            self.space_ok.d.next = true;
            self.len_ok.d.next = true;
            self.hold_ok.d.next = true;
            self.setup_ok.d.next = true;
        }
        // The queue and whether it is nonzero, registered together: the
        // zero test sits after the adder, not before `emit`.
        self.pending_q.d.next = self.pending_next.val();
        self.nonzero.d.next = self.pending_next.val().any();
        self.step.next = self.step_q.q.val();
        self.dir.next = self.dir_q.q.val();
        self.leave_up.next = self.emitted.q.val() & !self.dir_q.q.val();
        self.leave_down.next = self.emitted.q.val() & self.dir_q.q.val();
        // From flip-flops through a few LUTs, beside the adder's path.
        self.room_up.next = (self.pending_q.q.val() != self.pending_max.val())
            & (self.pending_q.q.val() != self.pending_max_less_one.val());
        self.room_down.next = (self.pending_q.q.val() != self.pending_min.val())
            & (self.pending_q.q.val() != self.pending_min_plus_one.val());
        self.pending.next = self.pending_q.q.val();
    }
}
