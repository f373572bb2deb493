//! Position moves of one pulse generator axis: a 64-deep FIFO of segments
//! (steps, start rate, acceleration; the jerks in a ring of their own) in
//! block RAM, a copy of its head segment in flip-flops, and the running
//! segment, which sets the NCO's rate, or the brake of a decelerating stop
//! (docs/pulse_generator.md).

use crate::probe::MoveEngineRegisters;
use motionhdl_spec::pulse::{
    ACCEL_FRAC_BITS, LOAD_FRACTION, RAMP_BITS, SEGMENT_FIFO_DEPTH, SEGMENT_SLOT_WORDS,
};
use motionhdl_spec::regmap;
use rust_hdl::prelude::*;

const DEPTH: usize = SEGMENT_FIFO_DEPTH;
/// Bits of the head and tail pointers (DEPTH is a power of two).
const PTR: usize = DEPTH.trailing_zeros() as usize;
/// Bits of the level, 0..=DEPTH.
const LEVEL: usize = PTR + 1;
/// Bits of a segment RAM address: slot, then word in the slot.
const RAM_ADDR: usize = PTR + 2;
/// Bits of the running rate and acceleration (32 and their fraction).
const RAMP: usize = RAMP_BITS as usize;
/// Bits of the jerk ring's pointers: twice the FIFO's depth, so the tail
/// never reaches the running segment's jerk.
const JERK_PTR: usize = PTR + 1;

/// The segment FIFO and the running segment. SEG_STEPS, SEG_RATE and
/// SEG_ACCEL go straight into the tail slot of the RAM (slot × 4 + field),
/// SEG_JERK into the tail entry of a second RAM, a ring twice as deep.
/// Whenever the head slot holds a segment and no copy of it is complete,
/// its steps and rate are read, one a clock, into the copy, and its accel
/// stays addressed, so the RAM's output register holds it for the load; a
/// segment loads from the copy and that output. The jerk RAM's output
/// holds the running segment's jerk (addressed at the load, so from the
/// segment's first advancing clock). A segment commands
/// exactly its `steps` steps (counted on `commanded`); on every clock the
/// NCO advances its rate (16 fraction bits) grows by the acceleration's
/// whole part and its acceleration (16 fraction bits) by `jerk`
/// (`motionhdl_spec::pulse::Segment`); `done` rises when the last
/// pushed segment has commanded all its steps. A `brake` (a decelerating
/// stop) empties the FIFO and runs the rate down from `brake_rate` by
/// `decel` each advancing clock until it reaches 0 (`braking`). Reset
/// clears every flip-flop; the RAM keeps its words.
///
/// The NCO's carry is registered (`commanded_q`) before it is counted, so
/// no path runs from the NCO's adder into this block's logic. That costs no
/// clock: the NCO never carries two clocks running (|rate| ≤ 2^31), so in
/// the clock after a segment's last step the segment is taken as ended
/// (`ending`, from flip-flops alone), as the unregistered count would have
/// ended it at that edge. [`MoveEngine::probe`] reports the registers as
/// that count would hold them.
#[derive(LogicBlock)]
pub struct MoveEngine {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// The axis runs moves (RUN bit and CTRL.MOVES): segments may load.
    pub run: Signal<In, Bit>,
    /// The NCO commanded a step this clock (registered here first).
    pub commanded: Signal<In, Bit>,
    /// The NCO's phase advanced this clock.
    pub advancing: Signal<In, Bit>,
    /// Push the tail slot at this edge (SEG_PUSH).
    pub push: Signal<In, Bit>,
    /// Write data for the tail slot's fields.
    pub wdata: Signal<In, Bits<32>>,
    /// Write `wdata` into the tail slot's steps (SEG_STEPS); dropped while
    /// the FIFO is full.
    pub write_steps: Signal<In, Bit>,
    /// The same for the start rate (SEG_RATE).
    pub write_rate: Signal<In, Bit>,
    /// The same for the acceleration (SEG_ACCEL).
    pub write_accel: Signal<In, Bit>,
    /// The same for the jerk (SEG_JERK).
    pub write_jerk: Signal<In, Bit>,
    /// Clear the sticky overflow flag.
    pub clear_overflow: Signal<In, Bit>,
    /// Drop the running segment and every queued one at this edge (the
    /// safety block's HALT): the FIFO empties and DONE clears; the RAM,
    /// the head pointer and OVERFLOW stay.
    pub flush: Signal<In, Bit>,
    /// FIFO_LOW_WATER.LEVEL (upper bits 0).
    pub low_water: Signal<In, Bits<32>>,
    /// A decelerating stop in this clock (the bank's): the FIFO empties as
    /// at `flush`, and unless braking already, braking starts at this
    /// edge from `brake_rate` with `decel`.
    pub brake: Signal<In, Bit>,
    /// The NCO's rate in this clock (RATE, or the running segment's).
    pub brake_rate: Signal<In, Bits<32>>,
    /// AX.DECEL (31 bits, upper bit 0).
    pub decel: Signal<In, Bits<32>>,
    /// Braking: the NCO runs at `rate` whatever RUN and CTRL.MOVES say.
    pub braking: Signal<Out, Bit>,
    /// The NCO rate: the running segment's, or 0.
    pub rate: Signal<Out, Bits<32>>,
    /// STATUS bits MOVING, DONE, OVERFLOW, FIFO_LEVEL and FIFO_LOW in place
    /// (the others 0).
    pub status: Signal<Out, Bits<32>>,
    active_q: DFF<Bit>,
    rate_q: DFF<Bits<RAMP>>,
    accel_q: DFF<Bits<RAMP>>,
    remaining: DFF<Bits<32>>,
    commanded_q: DFF<Bit>,
    last_q: DFF<Bit>,
    done_q: DFF<Bit>,
    overflow_q: DFF<Bit>,
    braking_q: DFF<Bit>,
    /// While braking: the rate's whole part is not 0 and heads against the
    /// acceleration (braking's test, registered: set from the rate that
    /// `rate_q` loads, so it holds for its output in this clock).
    against_q: DFF<Bit>,
    /// The head pointer with one more bit: the jerk ring's.
    head: DFF<Bits<JERK_PTR>>,
    count: DFF<Bits<LEVEL>>,
    // The head segment's copy: complete when `staged`; `fetch` counts the
    // words read so far (the RAM answers one clock after its address).
    staged: DFF<Bit>,
    fetch: DFF<Bits<2>>,
    staged_steps: DFF<Bits<32>>,
    staged_rate: DFF<Bits<32>>,
    ram: RAM<Bits<32>, RAM_ADDR>,
    jerks: RAM<Bits<32>, JERK_PTR>,
    one: Constant<Bits<32>>,
    two: Constant<Bits<32>>,
    full: Constant<Bits<LEVEL>>,
    word_shift: Constant<Bits<RAM_ADDR>>,
    word_steps: Constant<Bits<RAM_ADDR>>,
    word_rate: Constant<Bits<RAM_ADDR>>,
    word_accel: Constant<Bits<RAM_ADDR>>,
    frac_shift: Constant<Bits<6>>,
    ramp_sign: Constant<Bits<6>>,
    load_fraction: Constant<Bits<RAMP>>,
    sign_fill: Constant<Bits<RAMP>>,
    moving_bit: Constant<Bits<32>>,
    done_bit: Constant<Bits<32>>,
    overflow_bit: Constant<Bits<32>>,
    low_bit: Constant<Bits<32>>,
    braking_bit: Constant<Bits<32>>,
    level_shift: Constant<Bits<32>>,
    tail: Signal<Local, Bits<JERK_PTR>>,
    head_slot: Signal<Local, Bits<PTR>>,
    tail_slot: Signal<Local, Bits<PTR>>,
    ending: Signal<Local, Bit>,
    live: Signal<Local, Bit>,
    done_now: Signal<Local, Bit>,
    popped: Signal<Local, Bit>,
    ended: Signal<Local, Bit>,
    count_after_pop: Signal<Local, Bits<LEVEL>>,
    write_word: Signal<Local, Bits<RAM_ADDR>>,
    read_word: Signal<Local, Bits<RAM_ADDR>>,
    level_word: Signal<Local, Bits<32>>,
    status_word: Signal<Local, Bits<32>>,
    rate_out: Signal<Local, Bits<32>>,
    accel_whole: Signal<Local, Bits<RAMP>>,
    jerk_wide: Signal<Local, Bits<RAMP>>,
    rate_stepped: Signal<Local, Bits<RAMP>>,
    stepped_whole: Signal<Local, Bits<32>>,
    brake_valid: Signal<Local, Bit>,
    brake_accel: Signal<Local, Bits<32>>,
    out_whole: Signal<Local, Bits<32>>,
    out_braking: Signal<Local, Bit>,
}

impl Default for MoveEngine {
    fn default() -> Self {
        Self::new()
    }
}

impl MoveEngine {
    pub fn new() -> Self {
        const {
            assert!(DEPTH.is_power_of_two() && SEGMENT_SLOT_WORDS == 4);
        };
        let map = regmap::pulse_bank(1, 32);
        let status = map.array("AX").register("STATUS");
        let bit = |name: &str| {
            let f = status.field(name);
            assert_eq!(f.width, 1, "STATUS.{name}");
            Constant::new((1u64 << f.lsb).into())
        };
        let level = status.field("FIFO_LEVEL");
        assert_eq!(level.width as usize, LEVEL, "FIFO_LEVEL holds 0..=DEPTH");
        let word = |w: u64| Constant::new(w.into());
        Self {
            clock: Default::default(),
            reset: Default::default(),
            run: Default::default(),
            commanded: Default::default(),
            advancing: Default::default(),
            push: Default::default(),
            wdata: Default::default(),
            write_steps: Default::default(),
            write_rate: Default::default(),
            write_accel: Default::default(),
            write_jerk: Default::default(),
            clear_overflow: Default::default(),
            flush: Default::default(),
            low_water: Default::default(),
            brake: Default::default(),
            brake_rate: Default::default(),
            decel: Default::default(),
            braking: Default::default(),
            rate: Default::default(),
            status: Default::default(),
            active_q: Default::default(),
            rate_q: Default::default(),
            accel_q: Default::default(),
            remaining: Default::default(),
            commanded_q: Default::default(),
            last_q: Default::default(),
            done_q: Default::default(),
            overflow_q: Default::default(),
            braking_q: Default::default(),
            against_q: Default::default(),
            head: Default::default(),
            count: Default::default(),
            staged: Default::default(),
            fetch: Default::default(),
            staged_steps: Default::default(),
            staged_rate: Default::default(),
            ram: Default::default(),
            jerks: Default::default(),
            one: Constant::new(1.into()),
            two: Constant::new(2.into()),
            full: Constant::new((DEPTH as u64).into()),
            word_shift: word(2),
            word_steps: word(0),
            word_rate: word(1),
            word_accel: word(2),
            frac_shift: Constant::new(u64::from(ACCEL_FRAC_BITS).into()),
            ramp_sign: Constant::new((RAMP as u64 - 1).into()),
            load_fraction: Constant::new((LOAD_FRACTION as u64).into()),
            sign_fill: Constant::new((!0u64 << 32 & ((1 << RAMP) - 1)).into()),
            moving_bit: bit("MOVING"),
            done_bit: bit("DONE"),
            overflow_bit: bit("OVERFLOW"),
            low_bit: bit("FIFO_LOW"),
            braking_bit: bit("BRAKING"),
            level_shift: Constant::new((level.lsb as u64).into()),
            tail: Default::default(),
            head_slot: Default::default(),
            tail_slot: Default::default(),
            ending: Default::default(),
            live: Default::default(),
            done_now: Default::default(),
            popped: Default::default(),
            ended: Default::default(),
            count_after_pop: Default::default(),
            write_word: Default::default(),
            read_word: Default::default(),
            level_word: Default::default(),
            status_word: Default::default(),
            rate_out: Default::default(),
            accel_whole: Default::default(),
            jerk_wide: Default::default(),
            rate_stepped: Default::default(),
            stepped_whole: Default::default(),
            brake_valid: Default::default(),
            brake_accel: Default::default(),
            out_whole: Default::default(),
            out_braking: Default::default(),
        }
    }

    /// The registers, for comparison with the model: `active`,
    /// `remaining` and `done` as they would stand had the step registered
    /// in `commanded_q` been counted at the edge it was commanded; the jerk
    /// (the jerk RAM's output) while a segment runs, else 0.
    pub fn probe(&self) -> MoveEngineRegisters {
        let counted = self.active_q.q.val() && self.commanded_q.q.val();
        let remaining = self.remaining.q.val().index() as u32;
        let ending = counted && remaining == 1;
        let active = self.active_q.q.val() && !ending;
        MoveEngineRegisters {
            active,
            rate: self.rate_q.q.val().to_u64(),
            accel: self.accel_q.q.val().to_u64(),
            jerk: if active {
                self.jerks.read_data.val().index() as u32
            } else {
                0
            },
            remaining: remaining - u32::from(counted),
            done: self.done_q.q.val() || (ending && self.count.q.val().index() == 0),
            overflow: self.overflow_q.q.val(),
            level: self.count.q.val().index() as u32,
            staged: self.staged.q.val(),
            fetch: self.fetch.q.val().index() as u32,
            braking: self.braking_q.q.val(),
        }
    }
}

impl Logic for MoveEngine {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            active_q,
            rate_q,
            accel_q,
            remaining,
            commanded_q,
            last_q,
            done_q,
            overflow_q,
            braking_q,
            against_q,
            head,
            count,
            staged,
            fetch,
            staged_steps,
            staged_rate
        );
        self.ram.read_clock.next = self.clock.val();
        self.ram.write_clock.next = self.clock.val();
        self.jerks.read_clock.next = self.clock.val();
        self.jerks.write_clock.next = self.clock.val();
        self.tail.next = self.head.q.val() + self.count.q.val();
        self.head_slot.next = self.head.q.val().get_bits::<PTR>(0);
        self.tail_slot.next = self.tail.val().get_bits::<PTR>(0);
        // The head copy: the head slot's steps and rate are read into
        // flip-flops, one a clock, each arriving the clock after its
        // address. Its accel is read last and then stays addressed while
        // the copy is complete, so the RAM's output register holds it for
        // the load (the head slot is never written while it holds a
        // segment): 32 flip-flops fewer per axis.
        self.read_word.next = self.word_steps.val();
        if self.fetch.q.val() == 0 {
            if self.staged.q.val() {
                self.read_word.next = self.word_accel.val();
            } else if self.count.q.val().any() {
                self.fetch.d.next = 1.into();
            }
        } else if self.fetch.q.val() == 1 {
            self.read_word.next = self.word_rate.val();
            self.staged_steps.d.next = self.ram.read_data.val();
            self.fetch.d.next = 2.into();
        } else if self.fetch.q.val() == 2 {
            self.read_word.next = self.word_accel.val();
            self.staged_rate.d.next = self.ram.read_data.val();
            self.fetch.d.next = 3.into();
        } else {
            self.read_word.next = self.word_accel.val();
            self.staged.d.next = true;
            self.fetch.d.next = 0.into();
        }
        self.ram.read_address.next = (bit_cast::<RAM_ADDR, PTR>(self.head_slot.val())
            << self.word_shift.val())
            | self.read_word.val();
        // The acceleration's whole part and the jerk, sign-extended.
        self.accel_whole.next = self.accel_q.q.val() >> self.frac_shift.val();
        if self.accel_q.q.val().get_bit(self.ramp_sign.val().index()) {
            self.accel_whole.next = self.accel_whole.val() | self.sign_fill.val();
        }
        // Braking lasts while the rate still heads the way it started:
        // against the sign of the braking acceleration.
        self.brake_valid.next = self.braking_q.q.val() & self.against_q.q.val();
        // One rate step, shared by the running segment and the brake; its
        // braking test is computed before the NCO says whether it is taken
        // (`advancing` only selects it).
        self.rate_stepped.next = self.rate_q.q.val() + self.accel_whole.val();
        self.stepped_whole.next = self
            .rate_stepped
            .val()
            .get_bits::<32>(self.frac_shift.val().index());
        self.jerk_wide.next = bit_cast::<RAMP, 32>(self.jerks.read_data.val());
        if self.jerks.read_data.val().get_bit(31) {
            self.jerk_wide.next = self.jerk_wide.val() | self.sign_fill.val();
        }
        // The step the NCO commanded last clock is counted now; if it was
        // the segment's last, the segment is over in this clock already.
        self.ending.next = self.active_q.q.val() & self.commanded_q.q.val() & self.last_q.q.val();
        self.live.next = self.active_q.q.val() & !self.ending.val();
        self.commanded_q.d.next = self.commanded.val() & self.live.val();
        self.popped.next = false;
        self.ended.next = false;
        if self.active_q.q.val() & self.commanded_q.q.val() {
            self.remaining.d.next = self.remaining.q.val() - self.one.val();
            self.last_q.d.next = self.remaining.q.val() == self.two.val();
            if self.last_q.q.val() {
                self.active_q.d.next = false;
            }
        }
        if self.live.val() {
            if self.advancing.val() {
                self.rate_q.d.next = self.rate_stepped.val();
                self.accel_q.d.next = self.accel_q.q.val() + self.jerk_wide.val();
            }
        } else if self.run.val() & self.staged.q.val() & !self.braking_q.q.val() {
            self.popped.next = true;
            self.staged.d.next = false;
            self.head.d.next = self.head.q.val() + 1;
            self.active_q.d.next = self.staged_steps.q.val().any();
            self.ended.next = !self.staged_steps.q.val().any();
            self.rate_q.d.next = (bit_cast::<RAMP, 32>(self.staged_rate.q.val())
                << self.frac_shift.val())
                | self.load_fraction.val();
            self.accel_q.d.next = (bit_cast::<RAMP, 32>(self.ram.read_data.val())
                << self.frac_shift.val())
                | self.load_fraction.val();
            self.remaining.d.next = self.staged_steps.q.val();
            self.last_q.d.next = self.staged_steps.q.val() == self.one.val();
        }
        if self.braking_q.q.val() {
            if self.advancing.val() {
                self.rate_q.d.next = self.rate_stepped.val();
                self.against_q.d.next = self.stepped_whole.val().any()
                    & (self.stepped_whole.val().get_bit(31)
                        ^ self.accel_q.q.val().get_bit(self.ramp_sign.val().index()));
            }
            self.braking_q.d.next = self.brake_valid.val();
        }
        self.count_after_pop.next = self.count.q.val();
        if self.popped.val() {
            self.count_after_pop.next = self.count.q.val() - 1;
        }
        // DONE as the unregistered count would show it: a segment ending
        // now with nothing queued behind it (the count before this clock's
        // pop: a pop loads a segment that is still to run).
        self.done_now.next = self.ending.val() & !self.count.q.val().any();
        if self.done_now.val() | (self.ended.val() & !self.count_after_pop.val().any()) {
            self.done_q.d.next = true;
        }
        self.count.d.next = self.count_after_pop.val();
        // SEG_* writes land in the tail slot while there is room (the tail
        // names the same slot before and after a pop in this clock; it is
        // never the slot being copied, which holds a segment).
        self.write_word.next = 0.into();
        if self.write_rate.val() {
            self.write_word.next = self.word_rate.val();
        }
        if self.write_accel.val() {
            self.write_word.next = self.word_accel.val();
        }
        self.ram.write_address.next = (bit_cast::<RAM_ADDR, PTR>(self.tail_slot.val())
            << self.word_shift.val())
            | self.write_word.val();
        self.ram.write_data.next = self.wdata.val();
        self.ram.write_enable.next =
            (self.write_steps.val() | self.write_rate.val() | self.write_accel.val())
                & (self.count_after_pop.val() != self.full.val())
                & !self.reset.val();
        self.jerks.write_address.next = self.tail.val();
        self.jerks.write_data.next = self.wdata.val();
        self.jerks.write_enable.next = self.write_jerk.val()
            & (self.count_after_pop.val() != self.full.val())
            & !self.reset.val();
        // The running segment's jerk: the head's as it loads, then the
        // entry behind the head.
        self.jerks.read_address.next = self.head.q.val() - 1;
        if self.popped.val() {
            self.jerks.read_address.next = self.head.q.val();
        }
        if self.push.val() {
            if self.count_after_pop.val() == self.full.val() {
                self.overflow_q.d.next = true;
            } else {
                self.count.d.next = self.count_after_pop.val() + 1;
                self.done_q.d.next = false;
            }
        }
        if self.clear_overflow.val() {
            self.overflow_q.d.next = false;
        }
        if self.flush.val() | self.brake.val() {
            self.active_q.d.next = false;
            self.remaining.d.next = 0.into();
            self.commanded_q.d.next = false;
            self.last_q.d.next = false;
            self.done_q.d.next = false;
            self.count.d.next = 0.into();
            self.staged.d.next = false;
            self.fetch.d.next = 0.into();
        }
        if self.flush.val() {
            self.braking_q.d.next = false;
        }
        // Braking starts: rate and accel load as a segment's would, with
        // SEG_ACCEL = -DECEL heading up and +DECEL heading down.
        self.brake_accel.next = !self.decel.val() + self.one.val();
        if self.brake_rate.val().get_bit(31) {
            self.brake_accel.next = self.decel.val();
        }
        if self.brake.val() & !self.braking_q.q.val() {
            self.braking_q.d.next = true;
            // The brake's acceleration is against the rate by construction.
            self.against_q.d.next = self.brake_rate.val().any();
            self.rate_q.d.next = (bit_cast::<RAMP, 32>(self.brake_rate.val())
                << self.frac_shift.val())
                | self.load_fraction.val();
            self.accel_q.d.next = (bit_cast::<RAMP, 32>(self.brake_accel.val())
                << self.frac_shift.val())
                | self.load_fraction.val();
        }
        if self.reset.val() {
            self.active_q.d.next = false;
            self.rate_q.d.next = 0.into();
            self.accel_q.d.next = 0.into();
            self.remaining.d.next = 0.into();
            self.commanded_q.d.next = false;
            self.last_q.d.next = false;
            self.done_q.d.next = false;
            self.overflow_q.d.next = false;
            self.braking_q.d.next = false;
            self.against_q.d.next = false;
            self.head.d.next = 0.into();
            self.count.d.next = 0.into();
            self.staged.d.next = false;
            self.fetch.d.next = 0.into();
        }
        // One assignment to each output (see PulseGenerator::update).
        // From flip-flops only (not through `live`, which shares its block
        // with the NCO's inputs): Verilator then sees no loop through the
        // NCO.
        self.rate_out.next = 0.into();
        self.out_whole.next = self
            .rate_q
            .q
            .val()
            .get_bits::<32>(self.frac_shift.val().index());
        // Braking's test from flip-flops only: a 32-bit OR of the rate here
        // would sit on the path through the NCO into this block's enables
        // (a fifth of the 4-axis top's Fmax on the ECP5, docs/benchmarks.md).
        self.out_braking.next = self.braking_q.q.val() & self.against_q.q.val();
        if (self.active_q.q.val() & !(self.commanded_q.q.val() & self.last_q.q.val()))
            | self.out_braking.val()
        {
            self.rate_out.next = self.out_whole.val();
        }
        self.level_word.next = bit_cast::<32, LEVEL>(self.count.q.val());
        self.status_word.next = self.level_word.val() << self.level_shift.val();
        if self.live.val() {
            self.status_word.next = self.status_word.val() | self.moving_bit.val();
        }
        if self.done_q.q.val() | self.done_now.val() {
            self.status_word.next = self.status_word.val() | self.done_bit.val();
        }
        if self.overflow_q.q.val() {
            self.status_word.next = self.status_word.val() | self.overflow_bit.val();
        }
        if self.braking_q.q.val() {
            self.status_word.next = self.status_word.val() | self.braking_bit.val();
        }
        if self.level_word.val() <= self.low_water.val() {
            self.status_word.next = self.status_word.val() | self.low_bit.val();
        }
        self.rate.next = self.rate_out.val();
        self.braking.next = self.braking_q.q.val();
        self.status.next = self.status_word.val();
    }
}
