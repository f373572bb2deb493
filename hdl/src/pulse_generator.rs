//! Step/pulse generator of one axis: NCO, step queue and output timing
//! (docs/pulse_generator.md). S1/S2 feed the pulse-mode selector.

use crate::step_timer::StepTimer;
use motionhdl_spec::pulse::{PENDING_BITS, TIMER_BITS};
use rust_hdl::prelude::*;

const P: usize = PENDING_BITS as usize;
const T: usize = TIMER_BITS as usize;

/// One axis. Each clock with `enable`, the NCO adds |`rate`| to a 32-bit
/// phase; a carry commands one step in the direction of `rate`'s sign, so
/// the step frequency is |rate| × f_clk / 2^32, up to f_clk / 2. Commanded
/// steps wait in a signed queue until the timing allows them; when the
/// queue is full the NCO holds (the axis falls behind, it never drops a
/// step). `position` counts the steps emitted; `status` shows the queue.
#[derive(LogicBlock)]
pub struct PulseGenerator {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Run the NCO. Without it, queued steps still go out.
    pub enable: Signal<In, Bit>,
    /// Signed rate, two's complement: steps per clock = rate / 2^32.
    pub rate: Signal<In, Bits<32>>,
    /// The rate of the running segment, used instead of `rate` while
    /// `moves` is high.
    pub move_rate: Signal<In, Bits<32>>,
    /// Take the rate from `move_rate` (CTRL.MOVES).
    pub moves: Signal<In, Bit>,
    /// S1 high for at least this many clocks (0 counts as 1).
    pub step_len: Signal<In, Bits<T>>,
    /// S1 low for at least this many clocks between steps.
    pub step_space: Signal<In, Bits<T>>,
    /// S2 stable for at least this many clocks before S1 rises.
    pub dir_setup: Signal<In, Bits<T>>,
    /// S1 low for at least this many clocks before S2 changes.
    pub dir_hold: Signal<In, Bits<T>>,
    /// S1: step pulse.
    pub step: Signal<Out, Bit>,
    /// S2: direction, 1 = negative.
    pub dir: Signal<Out, Bit>,
    /// Steps emitted, signed, modulo 2^32.
    pub position: Signal<Out, Bits<32>>,
    /// The NCO commanded a step this clock (combinational).
    pub commanded: Signal<Out, Bit>,
    /// The NCO's phase advanced this clock (combinational).
    pub advancing: Signal<Out, Bit>,
    /// PULSE.AX[n].STATUS bits 16:0 as the register map lays it out: PENDING in
    /// bits 15:0, BUSY (steps pending or S1 high) in bit 16.
    pub status: Signal<Out, Bits<32>>,
    timer: StepTimer<P, T>,
    phase: DFF<Bits<32>>,
    position_q: DFF<Bits<32>>,
    one: Constant<Bits<32>>,
    minus_one: Constant<Bits<32>>,
    busy_bit: Constant<Bits<32>>,
    rate_selected: Signal<Local, Bits<32>>,
    busy_mask: Signal<Local, Bits<32>>,
    negative: Signal<Local, Bit>,
    magnitude: Signal<Local, Bits<32>>,
    sum: Signal<Local, Bits<33>>,
    blocked: Signal<Local, Bit>,
    request_up: Signal<Local, Bit>,
    request_down: Signal<Local, Bit>,
    position_step: Signal<Local, Bits<32>>,
}

impl Default for PulseGenerator {
    fn default() -> Self {
        Self::new()
    }
}

impl PulseGenerator {
    pub fn new() -> Self {
        const { assert!(P == 16, "STATUS.PENDING is 16 bits") };
        Self {
            clock: Default::default(),
            reset: Default::default(),
            enable: Default::default(),
            rate: Default::default(),
            move_rate: Default::default(),
            moves: Default::default(),
            step_len: Default::default(),
            step_space: Default::default(),
            dir_setup: Default::default(),
            dir_hold: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            position: Default::default(),
            status: Default::default(),
            commanded: Default::default(),
            advancing: Default::default(),
            timer: StepTimer::new(),
            phase: Default::default(),
            position_q: Default::default(),
            one: Constant::new(1.into()),
            minus_one: Constant::new(0xffff_ffffu64.into()),
            busy_bit: Constant::new((1u64 << 16).into()),
            rate_selected: Default::default(),
            busy_mask: Default::default(),
            negative: Default::default(),
            magnitude: Default::default(),
            sum: Default::default(),
            blocked: Default::default(),
            request_up: Default::default(),
            request_down: Default::default(),
            position_step: Default::default(),
        }
    }

    /// Every register, for comparison with the model.
    pub fn probe(&self) -> (u32, u32, crate::probe::StepTimerRegisters) {
        (
            self.phase.q.val().index() as u32,
            self.position_q.q.val().index() as u32,
            self.timer.probe(),
        )
    }
}

impl Logic for PulseGenerator {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, phase, position_q);
        self.timer.clock.next = self.clock.val();
        self.timer.reset.next = self.reset.val();
        self.timer.step_len.next = self.step_len.val();
        self.timer.step_space.next = self.step_space.val();
        self.timer.dir_setup.next = self.dir_setup.val();
        self.timer.dir_hold.next = self.dir_hold.val();
        // NCO.
        // Outputs other blocks read are set once per evaluation (defaults
        // go to Locals): Icarus wakes every reader on each assignment, and
        // two blocks that keep re-setting each other's inputs spin forever.
        self.rate_selected.next = self.rate.val();
        if self.moves.val() {
            self.rate_selected.next = self.move_rate.val();
        }
        self.negative.next = self.rate_selected.val().get_bit(31);
        self.magnitude.next = self.rate_selected.val();
        if self.negative.val() {
            self.magnitude.next = !self.rate_selected.val() + self.one.val();
        }
        self.sum.next =
            bit_cast::<33, 32>(self.phase.q.val()) + bit_cast::<33, 32>(self.magnitude.val());
        self.blocked.next = !self.timer.accept_up.val();
        if self.negative.val() {
            self.blocked.next = !self.timer.accept_down.val();
        }
        self.request_up.next = self.enable.val()
            & !self.blocked.val()
            & self.sum.val().get_bit(32)
            & !self.negative.val();
        self.request_down.next = self.enable.val()
            & !self.blocked.val()
            & self.sum.val().get_bit(32)
            & self.negative.val();
        self.timer.request_up.next = self.request_up.val();
        self.timer.request_down.next = self.request_down.val();
        self.commanded.next = self.request_up.val() | self.request_down.val();
        self.advancing.next = self.enable.val() & !self.blocked.val();
        if self.enable.val() & !self.blocked.val() {
            self.phase.d.next = self.sum.val().get_bits::<32>(0);
        }
        // Position: one adder.
        self.position_step.next = 0.into();
        if self.timer.emit_up.val() {
            self.position_step.next = self.one.val();
        }
        if self.timer.emit_down.val() {
            self.position_step.next = self.minus_one.val();
        }
        self.position_q.d.next = self.position_q.q.val() + self.position_step.val();
        if self.reset.val() {
            self.phase.d.next = 0.into();
            self.position_q.d.next = 0.into();
        }
        self.step.next = self.timer.step.val();
        self.dir.next = self.timer.dir.val();
        self.position.next = self.position_q.q.val();
        self.busy_mask.next = 0.into();
        if self.timer.pending.val().any() | self.timer.step.val() {
            self.busy_mask.next = self.busy_bit.val();
        }
        self.status.next = bit_cast::<32, P>(self.timer.pending.val()) | self.busy_mask.val();
    }
}
