//! Position moves of one pulse generator axis: a 64-deep FIFO of segments
//! (steps, start rate, rate increment per clock) in block RAM, a copy of its
//! head segment in flip-flops, and the running segment, which sets the
//! NCO's rate (docs/pulse_generator.md).

use crate::probe::MoveEngineRegisters;
use motionhdl_spec::pulse::{SEGMENT_FIFO_DEPTH, SEGMENT_SLOT_WORDS};
use motionhdl_spec::regmap;
use rust_hdl::prelude::*;

const DEPTH: usize = SEGMENT_FIFO_DEPTH;
/// Bits of the head and tail pointers (DEPTH is a power of two).
const PTR: usize = DEPTH.trailing_zeros() as usize;
/// Bits of the level, 0..=DEPTH.
const LEVEL: usize = PTR + 1;
/// Bits of a segment RAM address: slot, then word in the slot.
const RAM_ADDR: usize = PTR + 2;

/// The segment FIFO and the running segment. SEG_* writes go straight into
/// the tail slot of the RAM (slot × 4 + field). Whenever the head slot holds
/// a segment and no copy of it is complete, its three words are read, one a
/// clock, into the copy; a segment loads from the copy. A segment commands
/// exactly its `steps` steps (counted on `commanded`), its rate growing by
/// `accel` on every clock the NCO advances; `done` rises when the last
/// pushed segment has commanded all its steps. Reset clears every flip-flop;
/// the RAM keeps its words.
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
    /// The same for the rate increment (SEG_ACCEL).
    pub write_accel: Signal<In, Bit>,
    /// Clear the sticky overflow flag.
    pub clear_overflow: Signal<In, Bit>,
    /// FIFO_LOW_WATER.LEVEL (upper bits 0).
    pub low_water: Signal<In, Bits<32>>,
    /// The NCO rate: the running segment's, or 0.
    pub rate: Signal<Out, Bits<32>>,
    /// STATUS bits MOVING, DONE, OVERFLOW, FIFO_LEVEL and FIFO_LOW in place
    /// (the others 0).
    pub status: Signal<Out, Bits<32>>,
    active_q: DFF<Bit>,
    rate_q: DFF<Bits<32>>,
    accel_q: DFF<Bits<32>>,
    remaining: DFF<Bits<32>>,
    commanded_q: DFF<Bit>,
    last_q: DFF<Bit>,
    done_q: DFF<Bit>,
    overflow_q: DFF<Bit>,
    head: DFF<Bits<PTR>>,
    count: DFF<Bits<LEVEL>>,
    // The head segment's copy: complete when `staged`; `fetch` counts the
    // words read so far (the RAM answers one clock after its address).
    staged: DFF<Bit>,
    fetch: DFF<Bits<2>>,
    staged_steps: DFF<Bits<32>>,
    staged_rate: DFF<Bits<32>>,
    staged_accel: DFF<Bits<32>>,
    ram: RAM<Bits<32>, RAM_ADDR>,
    one: Constant<Bits<32>>,
    two: Constant<Bits<32>>,
    full: Constant<Bits<LEVEL>>,
    word_shift: Constant<Bits<RAM_ADDR>>,
    word_rate: Constant<Bits<RAM_ADDR>>,
    word_accel: Constant<Bits<RAM_ADDR>>,
    moving_bit: Constant<Bits<32>>,
    done_bit: Constant<Bits<32>>,
    overflow_bit: Constant<Bits<32>>,
    low_bit: Constant<Bits<32>>,
    level_shift: Constant<Bits<32>>,
    tail: Signal<Local, Bits<PTR>>,
    ending: Signal<Local, Bit>,
    live: Signal<Local, Bit>,
    done_now: Signal<Local, Bit>,
    popped: Signal<Local, Bit>,
    ended: Signal<Local, Bit>,
    count_after_pop: Signal<Local, Bits<LEVEL>>,
    write_word: Signal<Local, Bits<RAM_ADDR>>,
    level_word: Signal<Local, Bits<32>>,
    status_word: Signal<Local, Bits<32>>,
    rate_out: Signal<Local, Bits<32>>,
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
            clear_overflow: Default::default(),
            low_water: Default::default(),
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
            head: Default::default(),
            count: Default::default(),
            staged: Default::default(),
            fetch: Default::default(),
            staged_steps: Default::default(),
            staged_rate: Default::default(),
            staged_accel: Default::default(),
            ram: Default::default(),
            one: Constant::new(1.into()),
            two: Constant::new(2.into()),
            full: Constant::new((DEPTH as u64).into()),
            word_shift: word(2),
            word_rate: word(1),
            word_accel: word(2),
            moving_bit: bit("MOVING"),
            done_bit: bit("DONE"),
            overflow_bit: bit("OVERFLOW"),
            low_bit: bit("FIFO_LOW"),
            level_shift: Constant::new((level.lsb as u64).into()),
            tail: Default::default(),
            ending: Default::default(),
            live: Default::default(),
            done_now: Default::default(),
            popped: Default::default(),
            ended: Default::default(),
            count_after_pop: Default::default(),
            write_word: Default::default(),
            level_word: Default::default(),
            status_word: Default::default(),
            rate_out: Default::default(),
        }
    }

    /// The registers, for comparison with the model: `active`,
    /// `remaining` and `done` as they would stand had the step registered
    /// in `commanded_q` been counted at the edge it was commanded.
    pub fn probe(&self) -> MoveEngineRegisters {
        let counted = self.active_q.q.val() && self.commanded_q.q.val();
        let remaining = self.remaining.q.val().index() as u32;
        let ending = counted && remaining == 1;
        MoveEngineRegisters {
            active: self.active_q.q.val() && !ending,
            rate: self.rate_q.q.val().index() as u32,
            remaining: remaining - u32::from(counted),
            done: self.done_q.q.val() || (ending && self.count.q.val().index() == 0),
            overflow: self.overflow_q.q.val(),
            level: self.count.q.val().index() as u32,
            staged: self.staged.q.val(),
            fetch: self.fetch.q.val().index() as u32,
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
            head,
            count,
            staged,
            fetch,
            staged_steps,
            staged_rate,
            staged_accel
        );
        self.ram.read_clock.next = self.clock.val();
        self.ram.write_clock.next = self.clock.val();
        self.tail.next = self.head.q.val() + self.count.q.val().get_bits::<PTR>(0);
        // The head copy: word `fetch` of the head slot is addressed, the
        // word addressed last clock arrives.
        self.ram.read_address.next = (bit_cast::<RAM_ADDR, PTR>(self.head.q.val())
            << self.word_shift.val())
            | bit_cast::<RAM_ADDR, 2>(self.fetch.q.val());
        if self.fetch.q.val() == 0 {
            if !self.staged.q.val() & self.count.q.val().any() {
                self.fetch.d.next = 1.into();
            }
        } else if self.fetch.q.val() == 1 {
            self.staged_steps.d.next = self.ram.read_data.val();
            self.fetch.d.next = 2.into();
        } else if self.fetch.q.val() == 2 {
            self.staged_rate.d.next = self.ram.read_data.val();
            self.fetch.d.next = 3.into();
        } else {
            self.staged_accel.d.next = self.ram.read_data.val();
            self.staged.d.next = true;
            self.fetch.d.next = 0.into();
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
                self.rate_q.d.next = self.rate_q.q.val() + self.accel_q.q.val();
            }
        } else if self.run.val() & self.staged.q.val() {
            self.popped.next = true;
            self.staged.d.next = false;
            self.head.d.next = self.head.q.val() + 1;
            self.active_q.d.next = self.staged_steps.q.val().any();
            self.ended.next = !self.staged_steps.q.val().any();
            self.rate_q.d.next = self.staged_rate.q.val();
            self.accel_q.d.next = self.staged_accel.q.val();
            self.remaining.d.next = self.staged_steps.q.val();
            self.last_q.d.next = self.staged_steps.q.val() == self.one.val();
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
        self.ram.write_address.next = (bit_cast::<RAM_ADDR, PTR>(self.tail.val())
            << self.word_shift.val())
            | self.write_word.val();
        self.ram.write_data.next = self.wdata.val();
        self.ram.write_enable.next =
            (self.write_steps.val() | self.write_rate.val() | self.write_accel.val())
                & (self.count_after_pop.val() != self.full.val())
                & !self.reset.val();
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
        if self.reset.val() {
            self.active_q.d.next = false;
            self.rate_q.d.next = 0.into();
            self.accel_q.d.next = 0.into();
            self.remaining.d.next = 0.into();
            self.commanded_q.d.next = false;
            self.last_q.d.next = false;
            self.done_q.d.next = false;
            self.overflow_q.d.next = false;
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
        if self.active_q.q.val() & !(self.commanded_q.q.val() & self.last_q.q.val()) {
            self.rate_out.next = self.rate_q.q.val();
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
        if self.level_word.val() <= self.low_water.val() {
            self.status_word.next = self.status_word.val() | self.low_bit.val();
        }
        self.rate.next = self.rate_out.val();
        self.status.next = self.status_word.val();
    }
}
