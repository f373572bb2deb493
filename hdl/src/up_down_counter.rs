//! W-bit up/down counter split into two carry chains with a registered
//! look-ahead, so the longest carry path is W/2 bits instead of W.

use motionhdl_spec::bus::CounterParams;
use rust_hdl::prelude::*;

/// `count <= 0 if clear, count + load_value if load, (count ± step) mod 2^W
/// otherwise`, with a single-clock step of +1 (`up`) or −1 (`down`). Load
/// only a cleared counter with `up` and `down` low (clear it at the edge
/// before): the value goes in through the adder as its operand, so no
/// multiplexer sits between the adder and the flip-flops (the sum packs with
/// them on iCE40) and the carry-in is `up` itself.
///
/// The count is held as a low half of `W/2` bits and a high half. The high
/// half steps when the low half wraps; instead of waiting for the low half's
/// carry it reads two registered flags, `lo_max` (low half is all ones) and
/// `lo_nonzero`, kept true by the same next-state logic that moves the low
/// half. Both halves therefore change in the same clock and the count is
/// exactly that of one W-bit adder, but each carry chain is half as long
/// (iCE40 HX8K: a 28-bit chain alone reaches 147 MHz, two 14-bit ones 180).
/// `lo_nonzero` rather than `lo_zero` so that the all-zero power-up state is
/// consistent even before reset.
///
/// The flags' next state needs "low half = max − 1" (an up step reaches
/// max) and "low half = 1" (a down step reaches 0); the other cases are the
/// flags themselves (up from max wraps to 0, down from 0 to max). Both
/// compares are split: the low half's two lowest bits (the "base") are
/// compared directly, the bits above them (the "mid" bits) through two more
/// registered flags, `mid_ones` and `mid_zero`. Those are loaded every clock
/// from the mid bits as they stand (from `load_value`'s mid bits on a load),
/// so they lag the mid bits by one clock only after the base wrapped (it is
/// then 00 or 11, never the 10 or 01 the compares look for) and after a clear
/// (the base is then 00). So the look-ahead is a 2-bit compare and a
/// multiplexer, not a W/2-bit reduction, and the mid flags are a bare
/// reduction.
#[derive(LogicBlock)]
pub struct UpDownCounter {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Count +1 at this edge (registered upstream; not together with `down`).
    pub up: Signal<In, Bit>,
    /// Count −1 at this edge.
    pub down: Signal<In, Bit>,
    /// Clear to 0 at this edge; wins over `load` (a synchronous reset).
    pub clear: Signal<In, Bit>,
    /// Add `load_value mod 2^W` at this edge; only while the count is 0 and
    /// `up`, `down` are low, so that the count becomes `load_value`.
    pub load: Signal<In, Bit>,
    /// Value for `load`; bits at and above W are ignored.
    pub load_value: Signal<In, Bits<32>>,
    /// The low half of `load_value` is all ones ([`UpDownCounter::low_mask`]);
    /// given, not computed here, so that the compare is off the load path.
    pub load_low_is_max: Signal<In, Bit>,
    /// The low half of `load_value` is not 0.
    pub load_low_is_nonzero: Signal<In, Bit>,
    /// The count, zero-extended to 32 bits.
    pub count: Signal<Out, Bits<32>>,
    lo: DFF<Bits<32>>,
    hi: DFF<Bits<32>>,
    lo_max: DFF<Bit>,
    lo_nonzero: DFF<Bit>,
    mid_ones: DFF<Bit>,
    mid_zero: DFF<Bit>,
    lo_mask: Constant<Bits<32>>,
    base_mask: Constant<Bits<32>>,
    base_max_minus_one: Constant<Bits<32>>,
    mid_mask: Constant<Bits<32>>,
    hi_mask: Constant<Bits<32>>,
    lo_bits: Constant<Bits<5>>,
    shift1: Constant<Bits<5>>,
    one: Constant<Bits<32>>,
    load_hi: Signal<Local, Bits<32>>,
    base: Signal<Local, Bits<32>>,
    mid_source: Signal<Local, Bits<32>>,
    lo_step: Signal<Local, Bits<32>>,
    hi_step: Signal<Local, Bits<32>>,
    lo_carry_in: Signal<Local, Bits<32>>,
    hi_a: Signal<Local, Bits<32>>,
    hi_b: Signal<Local, Bits<32>>,
    load_lo: Signal<Local, Bits<32>>,
}

impl UpDownCounter {
    /// A `width`-bit counter, 2..=32.
    pub fn new(width: u32) -> Self {
        assert!(
            (2..=32).contains(&width),
            "width = {width} out of range 2..=32"
        );
        let lo_mask = Self::low_mask(width);
        let lo_bits = lo_mask.count_ones();
        let hi_mask = CounterParams::new(width, 1).count_mask() >> lo_bits;
        let k32 = |v: u32| Constant::new((v as u64).into());
        Self {
            clock: Default::default(),
            up: Default::default(),
            down: Default::default(),
            clear: Default::default(),
            load: Default::default(),
            load_value: Default::default(),
            load_low_is_max: Default::default(),
            load_low_is_nonzero: Default::default(),
            count: Default::default(),
            lo: Default::default(),
            hi: Default::default(),
            lo_max: Default::default(),
            lo_nonzero: Default::default(),
            mid_ones: Default::default(),
            mid_zero: Default::default(),
            lo_mask: k32(lo_mask),
            base_mask: k32(Self::base_mask(width)),
            base_max_minus_one: k32(Self::base_mask(width) - 1),
            mid_mask: k32(Self::mid_mask(width)),
            hi_mask: k32(hi_mask),
            lo_bits: Constant::new((lo_bits as u64).into()),
            shift1: Constant::new(1u64.into()),
            one: k32(1),
            load_hi: Default::default(),
            base: Default::default(),
            mid_source: Default::default(),
            lo_step: Default::default(),
            hi_step: Default::default(),
            lo_carry_in: Default::default(),
            hi_a: Default::default(),
            hi_b: Default::default(),
            load_lo: Default::default(),
        }
    }

    /// The bits of a `width`-bit count held in the low half.
    pub fn low_mask(width: u32) -> u32 {
        (1u32 << (width / 2)) - 1
    }

    /// The low half's lowest bits, compared directly by the look-ahead: two
    /// (one when the low half has only one bit).
    pub fn base_mask(width: u32) -> u32 {
        Self::low_mask(width) & 3
    }

    /// The low half's bits above [`UpDownCounter::base_mask`], summarised by
    /// the `mid_ones` / `mid_zero` flags (0 for W < 6: no such bits).
    pub fn mid_mask(width: u32) -> u32 {
        Self::low_mask(width) & !3
    }

    /// The count as a number.
    pub fn value(&self) -> u32 {
        self.count.val().to_u32()
    }

    /// The look-ahead contract: `lo_max` and `lo_nonzero` describe the low
    /// half exactly; `mid_ones` and `mid_zero` describe its mid bits
    /// whenever a step is pending (`up` or `down`) and the base is neither
    /// 00 nor 11, the only case in which they are read.
    pub fn lookahead_consistent(&self) -> bool {
        let lo = self.lo.q.val().to_u32();
        let mask = self.lo_mask.val().to_u32();
        let base_mask = self.base_mask.val().to_u32();
        let base = lo & base_mask;
        let mid_mask = self.mid_mask.val().to_u32();
        let mid = lo & mid_mask;
        let mid_ok =
            self.mid_ones.q.val() == (mid == mid_mask) && self.mid_zero.q.val() == (mid == 0);
        let base_wrapped = base == 0 || base == base_mask;
        let stepping = self.up.val() || self.down.val();
        self.lo_max.q.val() == (lo == mask)
            && self.lo_nonzero.q.val() == (lo != 0)
            && (!stepping || base_wrapped || mid_ok)
    }
}

impl Logic for UpDownCounter {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, lo, hi, lo_max, lo_nonzero, mid_ones, mid_zero);
        self.base.next = self.lo.q.val() & self.base_mask.val();

        // One adder per half: half + operand + carry-in. +1 is a carry-in
        // of 1, −1 an all-ones operand, a load the value as operand: each
        // operand bit is one LUT from flip-flops.
        self.load_lo.next = self.load_value.val() & self.lo_mask.val();
        self.load_hi.next = (self.load_value.val() >> self.lo_bits.val()) & self.hi_mask.val();
        self.lo_step.next = 0.into();
        self.hi_step.next = 0.into();
        self.lo_carry_in.next = 0.into();
        if self.up.val() {
            self.lo_carry_in.next = self.one.val();
        }
        if self.down.val() {
            self.lo_step.next = self.lo_mask.val();
            if !self.lo_nonzero.q.val() {
                self.hi_step.next = self.hi_mask.val();
            }
        }
        if self.load.val() {
            self.lo_step.next = self.load_lo.val();
            self.hi_step.next = self.load_hi.val();
        }
        self.lo.d.next =
            (self.lo.q.val() + self.lo_step.val() + self.lo_carry_in.val()) & self.lo_mask.val();
        // The high half's carry-in is `up` and `lo_max`, two flip-flops: it
        // is the carry out of an extra bottom bit that adds them, so no LUT
        // sits in front of the chain.
        self.hi_a.next = self.hi.q.val() << self.shift1.val();
        self.hi_b.next = self.hi_step.val() << self.shift1.val();
        if self.up.val() {
            self.hi_a.next = (self.hi.q.val() << self.shift1.val()) | self.one.val();
        }
        if self.lo_max.q.val() {
            self.hi_b.next = (self.hi_step.val() << self.shift1.val()) | self.one.val();
        }
        self.hi.d.next =
            ((self.hi_a.val() + self.hi_b.val()) >> self.shift1.val()) & self.hi_mask.val();

        // Flags of the low half after this edge. Up from max wraps to 0 and
        // down from 0 to max, so only "= max − 1" and "= 1" are compares,
        // of the base and the registered mid flags.
        if self.load.val() {
            self.lo_max.d.next = self.load_low_is_max.val();
            self.lo_nonzero.d.next = self.load_low_is_nonzero.val();
        } else if self.up.val() {
            self.lo_max.d.next =
                (self.base.val() == self.base_max_minus_one.val()) & self.mid_ones.q.val();
            self.lo_nonzero.d.next = !self.lo_max.q.val();
        } else if self.down.val() {
            self.lo_max.d.next = !self.lo_nonzero.q.val();
            self.lo_nonzero.d.next = !((self.base.val() == self.one.val()) & self.mid_zero.q.val());
        }
        // The mid flags follow the mid bits one clock behind, with no
        // clear or enable; on a load they take `load_value`'s mid bits, which
        // the low half holds after the edge.
        if self.load.val() {
            self.mid_source.next = self.load_value.val() & self.mid_mask.val();
        } else {
            self.mid_source.next = self.lo.q.val() & self.mid_mask.val();
        }
        self.mid_ones.d.next = self.mid_source.val() == self.mid_mask.val();
        self.mid_zero.d.next = !self.mid_source.val().any();
        if self.clear.val() {
            self.lo.d.next = 0.into();
            self.hi.d.next = 0.into();
            self.lo_max.d.next = false;
            self.lo_nonzero.d.next = false;
        }
        self.count.next = self.lo.q.val() | (self.hi.q.val() << self.lo_bits.val());
    }
}
