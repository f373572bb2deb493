//! The decoder and counter of one channel and nothing else: the smallest
//! useful ×4 quadrature counter, for projects that need no register bus.

use crate::step_decoder::StepDecoder;
use crate::up_down_counter::UpDownCounter;
use motionhdl_spec::regmap;
use rust_hdl::prelude::*;

/// Two-flop synchronisers, ×4 quadrature decoding and a `width`-bit
/// up/down counter; no filter, index, error logic or bus. It counts exactly
/// as a counter-bank channel in mode X4 with the filter off, with the same
/// latency from pin to count (docs/counter_bank.md), and wraps mod 2^W.
#[derive(LogicBlock)]
pub struct QuadratureCore {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high; clears the count (hold 4 clocks).
    pub reset: Signal<In, Bit>,
    /// Encoder A pin, asynchronous.
    pub a: Signal<In, Bit>,
    /// Encoder B pin, asynchronous.
    pub b: Signal<In, Bit>,
    /// The count, zero-extended to 32 bits.
    pub count: Signal<Out, Bits<32>>,
    sync1_a: DFF<Bit>,
    sync2_a: DFF<Bit>,
    level_a: DFF<Bit>,
    sync1_b: DFF<Bit>,
    sync2_b: DFF<Bit>,
    level_b: DFF<Bit>,
    a_prev: DFF<Bit>,
    b_prev: DFF<Bit>,
    decoder: StepDecoder,
    counter: UpDownCounter,
    mode_x4: Constant<Bits<3>>,
}

impl QuadratureCore {
    /// A core with a `width`-bit counter, 2..=32.
    pub fn new(width: u32) -> Self {
        Self {
            clock: Default::default(),
            reset: Default::default(),
            a: Default::default(),
            b: Default::default(),
            count: Default::default(),
            sync1_a: Default::default(),
            sync2_a: Default::default(),
            level_a: Default::default(),
            sync1_b: Default::default(),
            sync2_b: Default::default(),
            level_b: Default::default(),
            a_prev: Default::default(),
            b_prev: Default::default(),
            decoder: Default::default(),
            counter: UpDownCounter::new(width),
            mode_x4: Constant::new((regmap::mode::X4 as u64).into()),
        }
    }

    /// The count as a number.
    pub fn value(&self) -> u32 {
        self.counter.value()
    }

    /// The counter's look-ahead flags describe its low half.
    pub fn lookahead_consistent(&self) -> bool {
        self.counter.lookahead_consistent()
    }
}

impl Logic for QuadratureCore {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, sync1_a, sync2_a, level_a, sync1_b, sync2_b, level_b, a_prev, b_prev
        );
        // The same pipeline as a channel with F = 0: sync, sync, accept.
        self.sync1_a.d.next = self.a.val();
        self.sync2_a.d.next = self.sync1_a.q.val();
        self.level_a.d.next = self.sync2_a.q.val();
        self.sync1_b.d.next = self.b.val();
        self.sync2_b.d.next = self.sync1_b.q.val();
        self.level_b.d.next = self.sync2_b.q.val();
        self.a_prev.d.next = self.level_a.q.val();
        self.b_prev.d.next = self.level_b.q.val();

        self.decoder.clock.next = self.clock.val();
        self.decoder.hold.next = self.reset.val();
        self.decoder.a.next = self.level_a.q.val();
        self.decoder.b.next = self.level_b.q.val();
        self.decoder.a_prev.next = self.a_prev.q.val();
        self.decoder.b_prev.next = self.b_prev.q.val();
        self.decoder.mode.next = self.mode_x4.val();
        self.decoder.reverse.next = false;

        self.counter.clock.next = self.clock.val();
        self.counter.up.next = self.decoder.up_q.val();
        self.counter.down.next = self.decoder.down_q.val();
        self.counter.clear.next = self.reset.val();
        self.counter.load.next = false;
        self.counter.load_value.next = 0.into();
        self.counter.load_low_is_max.next = false;
        self.counter.load_low_is_nonzero.next = false;
        self.count.next = self.counter.count.val();
    }
}
