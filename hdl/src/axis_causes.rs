//! A pair of per-axis causes in the safety block, with their mask and
//! optionally an enable register: the soft limits (docs/safety_io.md,
//! "Soft limits": levels, enabled by SOFT_LIMIT_CTRL) and the counter
//! events (docs/safety_io.md, "Counter events": rises of each channel's
//! STATUS.ERR and SEEN).

use motionhdl_spec::regmap;
use rust_hdl::prelude::*;

pub use motionhdl_spec::safety_io::{CauseKind, COUNTER_EVENTS, SOFT_LIMITS};

/// Two causes per axis (`low` in bits N-1:0 of every register, `high` in
/// bits N+15:16), inside the safety block: writes decode `addr`/`we` as
/// the block does; `read_value` is the register at the block's latched
/// `read_addr` (0 for any other).
#[derive(LogicBlock)]
pub struct AxisCauses<const N: usize> {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Register bus word address.
    pub addr: Signal<In, Bits<7>>,
    /// Register bus write data.
    pub wdata: Signal<In, Bits<32>>,
    /// Write strobe.
    pub we: Signal<In, Bit>,
    /// The read address the safety block latched.
    pub read_addr: Signal<In, Bits<7>>,
    /// Per axis: the first cause's input.
    pub low: Signal<In, Bits<N>>,
    /// Per axis: the second cause's input.
    pub high: Signal<In, Bits<N>>,
    /// The addressed register of this part, or 0.
    pub read_value: Signal<Out, Bits<32>>,
    /// OR(cause AND mask).
    pub irq_active: Signal<Out, Bit>,
    /// Per axis: no step up (the first cause, for a kind that stops).
    pub stop_up: Signal<Out, Bits<N>>,
    /// Per axis: no step down (the second cause, likewise).
    pub stop_down: Signal<Out, Bits<N>>,
    ctrl: DFF<Bits<32>>,
    cause: DFF<Bits<32>>,
    mask: DFF<Bits<32>>,
    before: DFF<Bits<32>>,
    field_mask: Constant<Bits<32>>,
    has_ctrl: Constant<Bit>,
    on_rise: Constant<Bit>,
    stops: Constant<Bit>,
    shift: Constant<Bits<5>>,
    addr_ctrl: Constant<Bits<7>>,
    addr_cause: Constant<Bits<7>>,
    addr_mask: Constant<Bits<7>>,
    low_half: Signal<Local, Bits<32>>,
    high_half: Signal<Local, Bits<32>>,
    levels: Signal<Local, Bits<32>>,
    events: Signal<Local, Bits<32>>,
    kept: Signal<Local, Bits<32>>,
    word: Signal<Local, Bits<32>>,
}

impl<const N: usize> AxisCauses<N> {
    pub fn new(kind: CauseKind) -> Self {
        let map = regmap::safety_io(N as u32);
        let addr = |name: &str| Constant::new((map.register(name).offset as u64).into());
        let names = [kind.ctrl, Some(kind.cause), Some(kind.mask)];
        for r in names.into_iter().flatten().map(|n| map.register(n)) {
            assert_eq!((r.fields[0].lsb, r.fields[1].lsb), (0, 16), "{}", r.name);
        }
        let axes = (1u64 << N) - 1;
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            read_addr: Default::default(),
            low: Default::default(),
            high: Default::default(),
            read_value: Default::default(),
            irq_active: Default::default(),
            stop_up: Default::default(),
            stop_down: Default::default(),
            ctrl: Default::default(),
            cause: Default::default(),
            mask: Default::default(),
            before: Default::default(),
            field_mask: Constant::new((axes | axes << 16).into()),
            has_ctrl: Constant::new(kind.ctrl.is_some()),
            on_rise: Constant::new(kind.on_rise),
            stops: Constant::new(kind.stops),
            shift: Constant::new(16u64.into()),
            // Without a CTRL register its address is the cause's (never
            // decoded as CTRL: `has_ctrl` gates it).
            addr_ctrl: addr(kind.ctrl.unwrap_or(kind.cause)),
            addr_cause: addr(kind.cause),
            addr_mask: addr(kind.mask),
            low_half: Default::default(),
            high_half: Default::default(),
            levels: Default::default(),
            events: Default::default(),
            kept: Default::default(),
            word: Default::default(),
        }
    }

    /// (CTRL, CAUSE, MASK), for the checks (CTRL 0 without one).
    pub fn probe(&self) -> [u32; 3] {
        [
            self.ctrl.q.val().index() as u32,
            self.cause.q.val().index() as u32,
            self.mask.q.val().index() as u32,
        ]
    }
}

impl<const N: usize> Logic for AxisCauses<N> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, ctrl, cause, mask, before);
        // A cause sets while its input acts (a level) or where it rises;
        // a 1 written clears; the input wins.
        self.low_half.next = bit_cast::<32, N>(self.low.val());
        self.high_half.next = bit_cast::<32, N>(self.high.val());
        self.levels.next = self.low_half.val() | (self.high_half.val() << self.shift.val());
        self.events.next = self.levels.val();
        if self.has_ctrl.val() {
            self.events.next = self.levels.val() & self.ctrl.q.val();
        }
        if self.on_rise.val() {
            self.events.next = self.events.val() & !self.before.q.val();
        }
        self.before.d.next = self.levels.val();
        self.kept.next = self.cause.q.val();
        if self.we.val() & (self.addr.val() == self.addr_cause.val()) {
            self.kept.next = self.cause.q.val() & !self.wdata.val();
        }
        self.cause.d.next = self.kept.val() | self.events.val();
        if self.we.val() {
            if self.has_ctrl.val() & (self.addr.val() == self.addr_ctrl.val()) {
                self.ctrl.d.next = self.wdata.val() & self.field_mask.val();
            }
            if self.addr.val() == self.addr_mask.val() {
                self.mask.d.next = self.wdata.val() & self.field_mask.val();
            }
        }
        self.word.next = 0.into();
        if self.has_ctrl.val() & (self.read_addr.val() == self.addr_ctrl.val()) {
            self.word.next = self.ctrl.q.val();
        }
        if self.read_addr.val() == self.addr_cause.val() {
            self.word.next = self.cause.q.val();
        }
        if self.read_addr.val() == self.addr_mask.val() {
            self.word.next = self.mask.q.val();
        }
        if self.reset.val() {
            self.ctrl.d.next = 0.into();
            self.cause.d.next = 0.into();
            self.mask.d.next = 0.into();
            self.before.d.next = 0.into();
        }
        self.read_value.next = self.word.val();
        self.irq_active.next = (self.cause.q.val() & self.mask.q.val()).any();
        self.stop_up.next = 0.into();
        self.stop_down.next = 0.into();
        if self.stops.val() {
            self.stop_up.next = self.cause.q.val().get_bits::<N>(0);
            self.stop_down.next = self.cause.q.val().get_bits::<N>(16);
        }
    }
}
