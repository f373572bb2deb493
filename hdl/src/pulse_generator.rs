//! Step/pulse generator of one axis: NCO, step queue and output timing
//! (docs/pulse_generator.md). S1/S2 feed the pulse-mode selector.

use crate::step_timer::StepTimer;
use motionhdl_spec::pulse::{PENDING_BITS, TIMER_BITS};
use rust_hdl::prelude::*;

const P: usize = PENDING_BITS as usize;
const T: usize = TIMER_BITS as usize;

/// One axis. Each clock with `enable`, the NCO adds |`rate`| to a 32-bit
/// phase; a carry commands one step in the direction of `rate`'s sign, so
/// the step frequency is |rate| × f_clk / 2^32, up to f_clk / 2. The
/// command is registered and enters a signed queue of steps the next
/// clock; queued steps wait until the timing allows them. When the queue
/// is within two steps of full the NCO holds (the axis falls behind, it
/// never drops a step). `position` counts the steps emitted; `status`
/// shows the queue.
#[derive(LogicBlock)]
pub struct PulseGenerator {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Run the NCO. Without it, queued steps still go out.
    pub enable: Signal<In, Bit>,
    /// Stop now (the safety block's HALT): the NCO holds, queued steps are
    /// dropped, and from this edge S1 starts no step and S2 does not turn.
    pub halt: Signal<In, Bit>,
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
    /// Steps emitted, signed, modulo 2^32 (a step counts from the clock
    /// after S1 rose).
    pub position: Signal<Out, Bits<32>>,
    /// The NCO commanded a step this clock (combinational).
    pub commanded: Signal<Out, Bit>,
    /// The NCO's phase advanced this clock (combinational).
    pub advancing: Signal<Out, Bit>,
    /// PULSE.AX[n].STATUS bits 16:0 as the register map lays it out: PENDING in
    /// bits 15:0, BUSY (a step commanded and not yet out, or S1 high) in
    /// bit 16.
    pub status: Signal<Out, Bits<32>>,
    timer: StepTimer<P, T>,
    phase: DFF<Bits<32>>,
    position_q: DFF<Bits<32>>,
    command_up: DFF<Bit>,
    command_down: DFF<Bit>,
    one: Constant<Bits<32>>,
    /// -1 as a position step, and the mask that inverts a negative rate.
    all_ones: Constant<Bits<32>>,
    shift_sixteen: Constant<Bits<5>>,
    low_one: Constant<Bits<17>>,
    busy_bit: Constant<Bits<32>>,
    rate_selected: Signal<Local, Bits<32>>,
    busy_mask: Signal<Local, Bits<32>>,
    negative: Signal<Local, Bit>,
    rate_inverted: Signal<Local, Bits<32>>,
    carry_in: Signal<Local, Bits<17>>,
    sum_low: Signal<Local, Bits<17>>,
    sum_high: Signal<Local, Bits<17>>,
    sum_high_carried: Signal<Local, Bits<17>>,
    carry: Signal<Local, Bit>,
    phase_next: Signal<Local, Bits<32>>,
    phase_low: Signal<Local, Bits<16>>,
    phase_high: Signal<Local, Bits<16>>,
    rate_low: Signal<Local, Bits<16>>,
    rate_high: Signal<Local, Bits<16>>,
    phase_low_next: Signal<Local, Bits<16>>,
    phase_high_next: Signal<Local, Bits<16>>,
    blocked: Signal<Local, Bit>,
    advance: Signal<Local, Bit>,
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
            halt: Default::default(),
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
            command_up: Default::default(),
            command_down: Default::default(),
            one: Constant::new(1.into()),
            all_ones: Constant::new(0xffff_ffffu64.into()),
            shift_sixteen: Constant::new(16.into()),
            low_one: Constant::new(1.into()),
            busy_bit: Constant::new((1u64 << 16).into()),
            rate_selected: Default::default(),
            busy_mask: Default::default(),
            negative: Default::default(),
            rate_inverted: Default::default(),
            carry_in: Default::default(),
            sum_low: Default::default(),
            sum_high: Default::default(),
            sum_high_carried: Default::default(),
            carry: Default::default(),
            phase_next: Default::default(),
            phase_low: Default::default(),
            phase_high: Default::default(),
            rate_low: Default::default(),
            rate_high: Default::default(),
            phase_low_next: Default::default(),
            phase_high_next: Default::default(),
            blocked: Default::default(),
            advance: Default::default(),
            request_up: Default::default(),
            request_down: Default::default(),
            position_step: Default::default(),
        }
    }

    /// Every register, for comparison with the model.
    pub fn probe(&self) -> crate::probe::GeneratorRegisters {
        crate::probe::GeneratorRegisters {
            phase: self.phase.q.val().index() as u32,
            position: self.position_q.q.val().index() as u32,
            command: i8::from(self.command_up.q.val()) - i8::from(self.command_down.q.val()),
            timer: self.timer.probe(),
        }
    }
}

impl Logic for PulseGenerator {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, phase, position_q, command_up, command_down);
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
        self.rate_inverted.next = self.rate_selected.val();
        self.carry_in.next = 0.into();
        if self.negative.val() {
            self.rate_inverted.next = self.rate_selected.val() ^ self.all_ones.val();
            self.carry_in.next = self.low_one.val();
        }
        // phase + |rate| as carry chains: for a negative rate, |rate| =
        // !rate + 1 and the +1 is the carry into bit 0. The high half is
        // added both with and without the low half's carry (carry select),
        // so no chain is longer than 17 bits.
        self.phase_low.next = self.phase.q.val().get_bits::<16>(0);
        self.phase_high.next = self.phase.q.val().get_bits::<16>(16);
        self.rate_low.next = self.rate_inverted.val().get_bits::<16>(0);
        self.rate_high.next = self.rate_inverted.val().get_bits::<16>(16);
        self.sum_low.next = bit_cast::<17, 16>(self.phase_low.val())
            + bit_cast::<17, 16>(self.rate_low.val())
            + self.carry_in.val();
        self.sum_high.next =
            bit_cast::<17, 16>(self.phase_high.val()) + bit_cast::<17, 16>(self.rate_high.val());
        self.sum_high_carried.next = bit_cast::<17, 16>(self.phase_high.val())
            + bit_cast::<17, 16>(self.rate_high.val())
            + self.low_one.val();
        self.phase_low_next.next = self.sum_low.val().get_bits::<16>(0);
        self.carry.next = self.sum_high.val().get_bit(16);
        self.phase_high_next.next = self.sum_high.val().get_bits::<16>(0);
        if self.sum_low.val().get_bit(16) {
            self.carry.next = self.sum_high_carried.val().get_bit(16);
            self.phase_high_next.next = self.sum_high_carried.val().get_bits::<16>(0);
        }
        self.phase_next.next = (bit_cast::<32, 16>(self.phase_high_next.val())
            << self.shift_sixteen.val())
            | bit_cast::<32, 16>(self.phase_low_next.val());
        self.blocked.next = !self.timer.room_up.val();
        if self.negative.val() {
            self.blocked.next = !self.timer.room_down.val();
        }
        self.advance.next = self.enable.val() & !self.halt.val() & !self.blocked.val();
        self.timer.flush.next = self.halt.val();
        self.request_up.next = self.advance.val() & self.carry.val() & !self.negative.val();
        self.request_down.next = self.advance.val() & self.carry.val() & self.negative.val();
        // The command is registered: the queue adds it a clock later.
        self.command_up.d.next = self.request_up.val();
        self.command_down.d.next = self.request_down.val();
        self.timer.request_up.next = self.command_up.q.val();
        self.timer.request_down.next = self.command_down.q.val();
        self.commanded.next = self.request_up.val() | self.request_down.val();
        self.advancing.next = self.advance.val();
        if self.advance.val() {
            self.phase.d.next = self.phase_next.val();
        }
        // Position: one adder, fed by flip-flops (the step S1 started at
        // the last edge).
        self.position_step.next = 0.into();
        if self.timer.leave_up.val() {
            self.position_step.next = self.one.val();
        }
        if self.timer.leave_down.val() {
            self.position_step.next = self.all_ones.val();
        }
        self.position_q.d.next = self.position_q.q.val() + self.position_step.val();
        if self.reset.val() {
            self.phase.d.next = 0.into();
            self.position_q.d.next = 0.into();
            self.command_up.d.next = false;
            self.command_down.d.next = false;
        }
        self.step.next = self.timer.step.val();
        self.dir.next = self.timer.dir.val();
        self.position.next = self.position_q.q.val();
        self.busy_mask.next = 0.into();
        if self.timer.pending.val().any()
            | self.timer.step.val()
            | self.command_up.q.val()
            | self.command_down.q.val()
        {
            self.busy_mask.next = self.busy_bit.val();
        }
        self.status.next = bit_cast::<32, P>(self.timer.pending.val()) | self.busy_mask.val();
    }
}
