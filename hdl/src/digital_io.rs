//! The safety block's general-purpose I/O (docs/safety_io.md, "General-
//! purpose I/O"): GPIO_INPUTS inputs through the machine inputs' filter
//! with edge causes, and GPIO_OUTPUTS outputs, push-pull or open-drain,
//! that take their safe state when the card halts.

use crate::machine_inputs::PinFilter;
use motionhdl_spec::regmap;
use motionhdl_spec::safety_io::{GPIO_INPUTS, GPIO_OUTPUTS};
use rust_hdl::prelude::*;

const I: usize = GPIO_INPUTS as usize;
const O: usize = GPIO_OUTPUTS as usize;

/// The general-purpose inputs and outputs and their registers, inside the
/// safety block: writes decode `addr`/`we` as the block does; `read_value`
/// is the register at the block's latched `read_addr` (0 for any other).
#[derive(LogicBlock)]
pub struct DigitalIo {
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
    /// The machine inputs' filter tick.
    pub tick: Signal<In, Bit>,
    /// The e-stop latch or the bite flag is set after this edge: the
    /// outputs take their safe state.
    pub halting: Signal<In, Bit>,
    /// The input pins (asynchronous).
    pub gpi: Signal<In, Bits<I>>,
    /// Per output: the level driven while `gpo_oe` is 1.
    pub gpo_out: Signal<Out, Bits<O>>,
    /// Per output: drive the pin (else release it).
    pub gpo_oe: Signal<Out, Bits<O>>,
    /// The addressed register of this part, or 0.
    pub read_value: Signal<Out, Bits<32>>,
    /// OR(GPI_CAUSE AND GPI_MASK).
    pub irq_active: Signal<Out, Bit>,
    filters: Vec<PinFilter>,
    edge_ctrl: DFF<Bits<32>>,
    cause: DFF<Bits<I>>,
    mask: DFF<Bits<I>>,
    value: DFF<Bits<O>>,
    safe: DFF<Bits<O>>,
    open_drain: DFF<Bits<O>>,
    before: DFF<Bits<I>>,
    input_bit: Vec<Constant<Bits<I>>>,
    addr_level: Constant<Bits<7>>,
    addr_edge_ctrl: Constant<Bits<7>>,
    addr_cause: Constant<Bits<7>>,
    addr_mask: Constant<Bits<7>>,
    addr_value: Constant<Bits<7>>,
    addr_safe: Constant<Bits<7>>,
    addr_open_drain: Constant<Bits<7>>,
    levels: Signal<Local, Bits<I>>,
    events: Signal<Local, Bits<I>>,
    kept: Signal<Local, Bits<I>>,
    value_next: Signal<Local, Bits<O>>,
    word: Signal<Local, Bits<32>>,
}

impl Default for DigitalIo {
    fn default() -> Self {
        Self::new()
    }
}

impl DigitalIo {
    /// The block's GPIO_INPUTS inputs and GPIO_OUTPUTS outputs.
    pub fn new() -> Self {
        let map = regmap::safety_io(1);
        let addr = |name: &str| Constant::new((map.register(name).offset as u64).into());
        let edges = map.register("GPI_EDGE_CTRL");
        // RISE in the low half-word, FALL in the high one.
        assert_eq!((edges.field("RISE").lsb, edges.field("FALL").lsb), (0, 16));
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            read_addr: Default::default(),
            tick: Default::default(),
            halting: Default::default(),
            gpi: Default::default(),
            gpo_out: Default::default(),
            gpo_oe: Default::default(),
            read_value: Default::default(),
            irq_active: Default::default(),
            filters: (0..I).map(|_| PinFilter::default()).collect(),
            edge_ctrl: Default::default(),
            cause: Default::default(),
            mask: Default::default(),
            value: Default::default(),
            safe: Default::default(),
            open_drain: Default::default(),
            before: Default::default(),
            input_bit: (0..I).map(|i| Constant::new((1u64 << i).into())).collect(),
            addr_level: addr("GPI_LEVEL"),
            addr_edge_ctrl: addr("GPI_EDGE_CTRL"),
            addr_cause: addr("GPI_CAUSE"),
            addr_mask: addr("GPI_MASK"),
            addr_value: addr("GPO_VALUE"),
            addr_safe: addr("GPO_SAFE"),
            addr_open_drain: addr("GPO_OPEN_DRAIN"),
            levels: Default::default(),
            events: Default::default(),
            kept: Default::default(),
            value_next: Default::default(),
            word: Default::default(),
        }
    }

    /// (filtered levels, GPI_EDGE_CTRL, GPI_CAUSE, GPI_MASK, GPO_VALUE,
    /// GPO_SAFE, GPO_OPEN_DRAIN), for the checks.
    pub fn probe(&self) -> [u32; 7] {
        [
            crate::machine_inputs::levels(&self.filters),
            self.edge_ctrl.q.val().index() as u32,
            self.cause.q.val().index() as u32,
            self.mask.q.val().index() as u32,
            self.value.q.val().index() as u32,
            self.safe.q.val().index() as u32,
            self.open_drain.q.val().index() as u32,
        ]
    }
}

impl Logic for DigitalIo {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, edge_ctrl, cause, mask, value, safe, open_drain, before);
        self.levels.next = 0.into();
        for i in 0..I {
            self.filters[i].clock.next = self.clock.val();
            self.filters[i].reset.next = self.reset.val();
            self.filters[i].tick.next = self.tick.val();
            self.filters[i].pin.next = self.gpi.val().get_bit(i);
            if self.filters[i].level.val() {
                self.levels.next = self.levels.val() | self.input_bit[i].val();
            }
        }
        // A selected edge of the filtered level sets its cause; a 1
        // written clears; the event wins. (A DFF's `d` reads back its old
        // value: the kept bits are a Local.)
        self.events.next = (self.levels.val()
            & !self.before.q.val()
            & self.edge_ctrl.q.val().get_bits::<I>(0))
            | (!self.levels.val() & self.before.q.val() & self.edge_ctrl.q.val().get_bits::<I>(16));
        self.kept.next = self.cause.q.val();
        if self.we.val() & (self.addr.val() == self.addr_cause.val()) {
            self.kept.next = self.cause.q.val() & !self.wdata.val().get_bits::<I>(0);
        }
        self.cause.d.next = self.kept.val() | self.events.val();
        self.before.d.next = self.levels.val();
        self.value_next.next = self.value.q.val();
        if self.we.val() {
            if self.addr.val() == self.addr_edge_ctrl.val() {
                self.edge_ctrl.d.next = self.wdata.val();
            }
            if self.addr.val() == self.addr_mask.val() {
                self.mask.d.next = self.wdata.val().get_bits::<I>(0);
            }
            if self.addr.val() == self.addr_value.val() {
                self.value_next.next = self.wdata.val().get_bits::<O>(0);
            }
            if self.addr.val() == self.addr_safe.val() {
                self.safe.d.next = self.wdata.val().get_bits::<O>(0);
            }
            if self.addr.val() == self.addr_open_drain.val() {
                self.open_drain.d.next = self.wdata.val().get_bits::<O>(0);
            }
        }
        // Outputs take their safe state in the clock the card halts, and
        // keep it (writes lost) while it stays halted.
        if self.halting.val() {
            self.value_next.next = self.safe.q.val();
        }
        self.value.d.next = self.value_next.val();
        self.word.next = 0.into();
        if self.read_addr.val() == self.addr_level.val() {
            self.word.next = bit_cast::<32, I>(self.levels.val());
        }
        if self.read_addr.val() == self.addr_edge_ctrl.val() {
            self.word.next = self.edge_ctrl.q.val();
        }
        if self.read_addr.val() == self.addr_cause.val() {
            self.word.next = bit_cast::<32, I>(self.cause.q.val());
        }
        if self.read_addr.val() == self.addr_mask.val() {
            self.word.next = bit_cast::<32, I>(self.mask.q.val());
        }
        if self.read_addr.val() == self.addr_value.val() {
            self.word.next = bit_cast::<32, O>(self.value.q.val());
        }
        if self.read_addr.val() == self.addr_safe.val() {
            self.word.next = bit_cast::<32, O>(self.safe.q.val());
        }
        if self.read_addr.val() == self.addr_open_drain.val() {
            self.word.next = bit_cast::<32, O>(self.open_drain.q.val());
        }
        if self.reset.val() {
            self.edge_ctrl.d.next = 0.into();
            self.cause.d.next = 0.into();
            self.mask.d.next = 0.into();
            self.value.d.next = 0.into();
            self.safe.d.next = 0.into();
            self.open_drain.d.next = 0.into();
            self.before.d.next = 0.into();
        }
        self.read_value.next = self.word.val();
        self.irq_active.next = (self.cause.q.val() & self.mask.q.val()).any();
        // Push-pull drives the value; open-drain drives 0 and releases 1.
        self.gpo_out.next = self.value.q.val() & !self.open_drain.q.val();
        self.gpo_oe.next = !self.open_drain.q.val() | !self.value.q.val();
    }
}
