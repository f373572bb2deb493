//! Position moves of one pulse generator axis: a 2-deep FIFO of segments
//! (steps, start rate, rate increment per clock) and the running segment,
//! which sets the NCO's rate (docs/pulse_generator.md).

use motionhdl_spec::pulse::SEGMENT_FIFO_DEPTH;
use rust_hdl::prelude::*;

const DEPTH: usize = SEGMENT_FIFO_DEPTH;
/// Bits of the head and tail pointers (DEPTH is a power of two).
const PTR: usize = DEPTH.trailing_zeros() as usize;

/// The segment FIFO and the running segment. SEG_* writes go straight into
/// the FIFO's tail slot (no staging registers). A segment commands exactly
/// its `steps` steps (counted on `commanded`), its rate growing by `accel`
/// on every clock the NCO advances; then the next segment loads. `done`
/// rises when the last pushed segment has commanded all its steps.
#[derive(LogicBlock)]
pub struct MoveEngine {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// The axis runs moves (RUN bit and CTRL.MOVES): segments may load.
    pub run: Signal<In, Bit>,
    /// The NCO commanded a step this clock.
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
    /// The NCO rate: the running segment's, or 0.
    pub rate: Signal<Out, Bits<32>>,
    /// A segment is running.
    pub active: Signal<Out, Bit>,
    /// Sticky: every pushed segment has commanded its steps.
    pub done: Signal<Out, Bit>,
    /// Sticky: a push found the FIFO full.
    pub overflow: Signal<Out, Bit>,
    /// Segments waiting.
    pub level: Signal<Out, Bits<3>>,
    active_q: DFF<Bit>,
    rate_q: DFF<Bits<32>>,
    accel_q: DFF<Bits<32>>,
    remaining: DFF<Bits<32>>,
    done_q: DFF<Bit>,
    overflow_q: DFF<Bit>,
    head: DFF<Bits<PTR>>,
    count: DFF<Bits<3>>,
    fifo_steps: Vec<DFF<Bits<32>>>,
    fifo_rate: Vec<DFF<Bits<32>>>,
    fifo_accel: Vec<DFF<Bits<32>>>,
    slot: Vec<Constant<Bits<PTR>>>,
    one: Constant<Bits<32>>,
    full: Constant<Bits<3>>,
    head_steps: Signal<Local, Bits<32>>,
    head_rate: Signal<Local, Bits<32>>,
    head_accel: Signal<Local, Bits<32>>,
    tail: Signal<Local, Bits<PTR>>,
    popped: Signal<Local, Bit>,
    ended: Signal<Local, Bit>,
    count_after_pop: Signal<Local, Bits<3>>,
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
            assert!(
                DEPTH.is_power_of_two() && DEPTH < 8,
                "pointers wrap; count is Bits<3>"
            )
        };
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
            rate: Default::default(),
            active: Default::default(),
            done: Default::default(),
            overflow: Default::default(),
            level: Default::default(),
            active_q: Default::default(),
            rate_q: Default::default(),
            accel_q: Default::default(),
            remaining: Default::default(),
            done_q: Default::default(),
            overflow_q: Default::default(),
            head: Default::default(),
            count: Default::default(),
            fifo_steps: (0..DEPTH).map(|_| Default::default()).collect(),
            fifo_rate: (0..DEPTH).map(|_| Default::default()).collect(),
            fifo_accel: (0..DEPTH).map(|_| Default::default()).collect(),
            slot: (0..DEPTH as u64).map(|j| Constant::new(j.into())).collect(),
            one: Constant::new(1.into()),
            full: Constant::new((DEPTH as u64).into()),
            head_steps: Default::default(),
            head_rate: Default::default(),
            head_accel: Default::default(),
            tail: Default::default(),
            popped: Default::default(),
            ended: Default::default(),
            count_after_pop: Default::default(),
            rate_out: Default::default(),
        }
    }

    /// (active, rate, remaining, done, overflow, level), for comparison
    /// with the model.
    pub fn probe(&self) -> (bool, u32, u32, bool, bool, u32) {
        (
            self.active_q.q.val(),
            self.rate_q.q.val().index() as u32,
            self.remaining.q.val().index() as u32,
            self.done_q.q.val(),
            self.overflow_q.q.val(),
            self.count.q.val().index() as u32,
        )
    }
}

impl Logic for MoveEngine {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, active_q, rate_q, accel_q, remaining, done_q, overflow_q, head, count
        );
        self.head_steps.next = 0.into();
        self.head_rate.next = 0.into();
        self.head_accel.next = 0.into();
        self.tail.next = self.head.q.val() + self.count.q.val().get_bits::<PTR>(0);
        for j in 0..DEPTH {
            self.fifo_steps[j].clock.next = self.clock.val();
            self.fifo_rate[j].clock.next = self.clock.val();
            self.fifo_accel[j].clock.next = self.clock.val();
            self.fifo_steps[j].d.next = self.fifo_steps[j].q.val();
            self.fifo_rate[j].d.next = self.fifo_rate[j].q.val();
            self.fifo_accel[j].d.next = self.fifo_accel[j].q.val();
            if self.head.q.val() == self.slot[j].val() {
                self.head_steps.next = self.fifo_steps[j].q.val();
                self.head_rate.next = self.fifo_rate[j].q.val();
                self.head_accel.next = self.fifo_accel[j].q.val();
            }
        }
        self.popped.next = false;
        self.ended.next = false;
        if self.active_q.q.val() {
            if self.commanded.val() {
                self.remaining.d.next = self.remaining.q.val() - self.one.val();
                if self.remaining.q.val() == self.one.val() {
                    self.active_q.d.next = false;
                    self.ended.next = true;
                }
            }
            if self.advancing.val() {
                self.rate_q.d.next = self.rate_q.q.val() + self.accel_q.q.val();
            }
        } else if self.run.val() & self.count.q.val().any() {
            self.popped.next = true;
            self.head.d.next = self.head.q.val() + 1;
            self.active_q.d.next = self.head_steps.val().any();
            self.ended.next = !self.head_steps.val().any();
            self.rate_q.d.next = self.head_rate.val();
            self.accel_q.d.next = self.head_accel.val();
            self.remaining.d.next = self.head_steps.val();
        }
        self.count_after_pop.next = self.count.q.val();
        if self.popped.val() {
            self.count_after_pop.next = self.count.q.val() - 1;
        }
        if self.ended.val() & !self.count_after_pop.val().any() {
            self.done_q.d.next = true;
        }
        self.count.d.next = self.count_after_pop.val();
        // SEG_* writes land in the tail slot while there is room (the tail
        // names the same slot before and after a pop in this clock).
        if self.count_after_pop.val() != self.full.val() {
            for j in 0..DEPTH {
                if self.tail.val() == self.slot[j].val() {
                    if self.write_steps.val() {
                        self.fifo_steps[j].d.next = self.wdata.val();
                    }
                    if self.write_rate.val() {
                        self.fifo_rate[j].d.next = self.wdata.val();
                    }
                    if self.write_accel.val() {
                        self.fifo_accel[j].d.next = self.wdata.val();
                    }
                }
            }
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
        if self.reset.val() {
            self.active_q.d.next = false;
            self.rate_q.d.next = 0.into();
            self.accel_q.d.next = 0.into();
            self.remaining.d.next = 0.into();
            self.done_q.d.next = false;
            self.overflow_q.d.next = false;
            self.head.d.next = 0.into();
            self.count.d.next = 0.into();
            for j in 0..DEPTH {
                self.fifo_steps[j].d.next = 0.into();
                self.fifo_rate[j].d.next = 0.into();
                self.fifo_accel[j].d.next = 0.into();
            }
        }
        // One assignment to the output (see PulseGenerator::update).
        self.rate_out.next = 0.into();
        if self.active_q.q.val() {
            self.rate_out.next = self.rate_q.q.val();
        }
        self.rate.next = self.rate_out.val();
        self.active.next = self.active_q.q.val();
        self.done.next = self.done_q.q.val();
        self.overflow.next = self.overflow_q.q.val();
        self.level.next = self.count.q.val();
    }
}
