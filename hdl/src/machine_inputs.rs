//! The safety block's machine inputs (docs/safety_io.md, "Limits, home and
//! alarm"): per axis LIMIT_POS, LIMIT_NEG, HOME and ALARM through a
//! synchroniser and a filter timed by one shared prescaler; polarity,
//! enable, sticky causes, masks and the per-direction stops.

use motionhdl_spec::regmap;
use motionhdl_spec::safety_io::{FILTER_PRESCALER_BITS, FILTER_TICKS};
use rust_hdl::prelude::*;

const TICK_BITS: usize = FILTER_PRESCALER_BITS as usize;

/// One input's two synchroniser flip-flops and filter: at a tick, the
/// filtered `level` takes the synchronised pin once it has read the new
/// level at FILTER_TICKS ticks in a row.
#[derive(LogicBlock)]
pub struct PinFilter {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high: everything 0.
    pub reset: Signal<In, Bit>,
    /// The pin (asynchronous).
    pub pin: Signal<In, Bit>,
    /// The prescaler's tick.
    pub tick: Signal<In, Bit>,
    /// The filtered level (a flip-flop).
    pub level: Signal<Out, Bit>,
    meta: DFF<Bit>,
    sync: DFF<Bit>,
    held: DFF<Bit>,
    count: DFF<Bits<2>>,
    one: Constant<Bits<2>>,
}

impl Default for PinFilter {
    fn default() -> Self {
        Self {
            clock: Default::default(),
            reset: Default::default(),
            pin: Default::default(),
            tick: Default::default(),
            level: Default::default(),
            meta: Default::default(),
            sync: Default::default(),
            held: Default::default(),
            count: Default::default(),
            one: Constant::new(1.into()),
        }
    }
}

// The count is two bits: ticks in a row, less one.
const _: () = assert!(FILTER_TICKS == 4);

impl Logic for PinFilter {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, meta, sync, held, count);
        self.meta.d.next = self.pin.val();
        self.sync.d.next = self.meta.q.val();
        if self.tick.val() {
            if self.sync.q.val() == self.held.q.val() {
                self.count.d.next = 0.into();
            } else if self.count.q.val().all() {
                self.held.d.next = self.sync.q.val();
                self.count.d.next = 0.into();
            } else {
                self.count.d.next = self.count.q.val() + self.one.val();
            }
        }
        if self.reset.val() {
            self.meta.d.next = false;
            self.sync.d.next = false;
            self.held.d.next = false;
            self.count.d.next = 0.into();
        }
        self.level.next = self.held.q.val();
    }
}

/// The filtered levels of `filters`, bit i = filter i, for the checks.
pub fn levels(filters: &[PinFilter]) -> u32 {
    filters
        .iter()
        .enumerate()
        .fold(0, |bits, (i, f)| bits | u32::from(f.held.q.val()) << i)
}

/// The machine inputs of `N` axes and their registers, inside the safety
/// block: writes decode `addr`/`we` as the block does; `read_value` is the
/// register at the block's latched `read_addr` (0 for any other address).
#[derive(LogicBlock)]
pub struct MachineStops<const N: usize> {
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
    /// LIMIT_POS pins, bit i = axis i.
    pub limit_pos: Signal<In, Bits<N>>,
    /// LIMIT_NEG pins.
    pub limit_neg: Signal<In, Bits<N>>,
    /// HOME pins.
    pub home: Signal<In, Bits<N>>,
    /// ALARM pins.
    pub alarm: Signal<In, Bits<N>>,
    /// The addressed register of this part, or 0.
    pub read_value: Signal<Out, Bits<32>>,
    /// OR(cause AND mask) over LIMIT_CAUSE and HOME_ALARM_CAUSE.
    pub irq_active: Signal<Out, Bit>,
    /// Per axis: no step in the positive direction.
    pub stop_up: Signal<Out, Bits<N>>,
    /// Per axis: no step in the negative direction.
    pub stop_down: Signal<Out, Bits<N>>,
    /// Per axis: the enabled HOME input turns active (its cause sets at
    /// this clock's edge); gates of flip-flops.
    pub home_event: Signal<Out, Bits<N>>,
    /// The filters' tick (the general-purpose inputs' filters share it).
    pub tick: Signal<Out, Bit>,
    pos_filters: Vec<PinFilter>,
    neg_filters: Vec<PinFilter>,
    home_filters: Vec<PinFilter>,
    alarm_filters: Vec<PinFilter>,
    prescaler: DFF<Bits<TICK_BITS>>,
    pos_ctrl: DFF<Bits<32>>,
    neg_ctrl: DFF<Bits<32>>,
    home_ctrl: DFF<Bits<32>>,
    alarm_ctrl: DFF<Bits<32>>,
    limit_cause: DFF<Bits<32>>,
    limit_mask: DFF<Bits<32>>,
    home_alarm_cause: DFF<Bits<32>>,
    home_alarm_mask: DFF<Bits<32>>,
    home_stop: DFF<Bits<N>>,
    home_before: DFF<Bits<N>>,
    /// "The prescaler is 0", registered: computed a clock early from the
    /// prescaler's next value, so the decrement's carry chain ends at a
    /// flip-flop instead of fanning out to every filter.
    ticking: DFF<Bit>,
    single: Constant<Bit>,
    tick_reload: Constant<Bits<TICK_BITS>>,
    tick_one: Constant<Bits<TICK_BITS>>,
    ctrl_mask: Constant<Bits<32>>,
    shift: Constant<Bits<5>>,
    axis_bit: Vec<Constant<Bits<N>>>,
    addr_pos_ctrl: Constant<Bits<7>>,
    addr_neg_ctrl: Constant<Bits<7>>,
    addr_home_ctrl: Constant<Bits<7>>,
    addr_alarm_ctrl: Constant<Bits<7>>,
    addr_limit_inputs: Constant<Bits<7>>,
    addr_home_alarm_inputs: Constant<Bits<7>>,
    addr_limit_cause: Constant<Bits<7>>,
    addr_limit_mask: Constant<Bits<7>>,
    addr_home_alarm_cause: Constant<Bits<7>>,
    addr_home_alarm_mask: Constant<Bits<7>>,
    addr_home_stop: Constant<Bits<7>>,
    /// Per axis: stopped both ways (an alarm, or home with HOME_STOP).
    stop_both: Signal<Local, Bits<N>>,
    pos_level: Signal<Local, Bits<N>>,
    neg_level: Signal<Local, Bits<N>>,
    home_level: Signal<Local, Bits<N>>,
    alarm_level: Signal<Local, Bits<N>>,
    pos_active: Signal<Local, Bits<N>>,
    neg_active: Signal<Local, Bits<N>>,
    home_active: Signal<Local, Bits<N>>,
    alarm_active: Signal<Local, Bits<N>>,
    home_acting: Signal<Local, Bits<N>>,
    pos_acting: Signal<Local, Bits<N>>,
    neg_acting: Signal<Local, Bits<N>>,
    alarm_acting: Signal<Local, Bits<N>>,
    low_half: Signal<Local, Bits<32>>,
    high_half: Signal<Local, Bits<32>>,
    limit_events: Signal<Local, Bits<32>>,
    limit_kept: Signal<Local, Bits<32>>,
    home_alarm_kept: Signal<Local, Bits<32>>,
    value: Signal<Local, Bits<32>>,
}

impl<const N: usize> MachineStops<N> {
    /// `N` axes (1..=16) with a filter tick every `tick_clocks` clocks.
    pub fn new(tick_clocks: u32) -> Self {
        assert!((1..=16).contains(&N), "axes = {N} out of range 1..=16");
        assert!(
            (1..1 << TICK_BITS).contains(&tick_clocks),
            "tick_clocks = {tick_clocks} out of range 1..{}",
            1u32 << TICK_BITS
        );
        let map = regmap::safety_io(N as u32);
        let addr = |name: &str| Constant::new((map.register(name).offset as u64).into());
        let ctrl = map.register("LIMIT_POS_CTRL");
        // Fields at bits 0 and 16 in every register of the part (the shift
        // below moves the second one).
        for name in [
            "LIMIT_INPUTS",
            "LIMIT_CAUSE",
            "HOME_ALARM_INPUTS",
            "HOME_ALARM_CAUSE",
        ] {
            assert_eq!(map.register(name).fields[1].lsb, 16, "{name}");
        }
        assert_eq!(ctrl.field("ACTIVE_LOW").lsb, 16);
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            read_addr: Default::default(),
            limit_pos: Default::default(),
            limit_neg: Default::default(),
            home: Default::default(),
            alarm: Default::default(),
            read_value: Default::default(),
            irq_active: Default::default(),
            stop_up: Default::default(),
            stop_down: Default::default(),
            pos_filters: (0..N).map(|_| PinFilter::default()).collect(),
            neg_filters: (0..N).map(|_| PinFilter::default()).collect(),
            home_filters: (0..N).map(|_| PinFilter::default()).collect(),
            alarm_filters: (0..N).map(|_| PinFilter::default()).collect(),
            prescaler: Default::default(),
            pos_ctrl: Default::default(),
            neg_ctrl: Default::default(),
            home_ctrl: Default::default(),
            alarm_ctrl: Default::default(),
            limit_cause: Default::default(),
            limit_mask: Default::default(),
            home_alarm_cause: Default::default(),
            home_alarm_mask: Default::default(),
            home_stop: Default::default(),
            home_before: Default::default(),
            ticking: Default::default(),
            single: Constant::new(tick_clocks == 1),
            tick_reload: Constant::new(((tick_clocks - 1) as u64).into()),
            tick_one: Constant::new(1.into()),
            ctrl_mask: Constant::new((ctrl.writable_mask() as u64).into()),
            shift: Constant::new(16.into()),
            axis_bit: (0..N).map(|i| Constant::new((1u64 << i).into())).collect(),
            addr_pos_ctrl: addr("LIMIT_POS_CTRL"),
            addr_neg_ctrl: addr("LIMIT_NEG_CTRL"),
            addr_home_ctrl: addr("HOME_CTRL"),
            addr_alarm_ctrl: addr("ALARM_CTRL"),
            addr_limit_inputs: addr("LIMIT_INPUTS"),
            addr_home_alarm_inputs: addr("HOME_ALARM_INPUTS"),
            addr_limit_cause: addr("LIMIT_CAUSE"),
            addr_limit_mask: addr("LIMIT_MASK"),
            addr_home_alarm_cause: addr("HOME_ALARM_CAUSE"),
            addr_home_alarm_mask: addr("HOME_ALARM_MASK"),
            addr_home_stop: addr("HOME_STOP"),
            stop_both: Default::default(),
            tick: Default::default(),
            pos_level: Default::default(),
            neg_level: Default::default(),
            home_level: Default::default(),
            alarm_level: Default::default(),
            pos_active: Default::default(),
            neg_active: Default::default(),
            home_active: Default::default(),
            alarm_active: Default::default(),
            home_acting: Default::default(),
            pos_acting: Default::default(),
            neg_acting: Default::default(),
            alarm_acting: Default::default(),
            home_event: Default::default(),
            low_half: Default::default(),
            high_half: Default::default(),
            limit_events: Default::default(),
            limit_kept: Default::default(),
            home_alarm_kept: Default::default(),
            value: Default::default(),
        }
    }
}

impl<const N: usize> MachineStops<N> {
    /// (filtered levels, CTRL registers, LIMIT_CAUSE, LIMIT_MASK,
    /// HOME_ALARM_CAUSE, HOME_ALARM_MASK), for the contract checks.
    pub fn probe(&self) -> ([u32; 4], [u32; 4], [u32; 4]) {
        let word = |d: &DFF<Bits<32>>| d.q.val().index() as u32;
        (
            [
                levels(&self.pos_filters),
                levels(&self.neg_filters),
                levels(&self.home_filters),
                levels(&self.alarm_filters),
            ],
            [
                word(&self.pos_ctrl),
                word(&self.neg_ctrl),
                word(&self.home_ctrl),
                word(&self.alarm_ctrl),
            ],
            [
                word(&self.limit_cause),
                word(&self.limit_mask),
                word(&self.home_alarm_cause),
                word(&self.home_alarm_mask),
            ],
        )
    }
}

impl<const N: usize> Logic for MachineStops<N> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            prescaler,
            ticking,
            pos_ctrl,
            neg_ctrl,
            home_ctrl,
            alarm_ctrl,
            limit_cause,
            limit_mask,
            home_alarm_cause,
            home_alarm_mask,
            home_stop,
            home_before
        );
        // One tick every tick_reload + 1 clocks for every filter: at the
        // clocks where the prescaler is 0 (`ticking` tracks that).
        self.tick.next = self.ticking.q.val();
        if self.ticking.q.val() {
            self.prescaler.d.next = self.tick_reload.val();
            self.ticking.d.next = self.single.val();
        } else {
            self.prescaler.d.next = self.prescaler.q.val() - self.tick_one.val();
            self.ticking.d.next = self.prescaler.q.val() == self.tick_one.val();
        }
        self.pos_level.next = 0.into();
        self.neg_level.next = 0.into();
        self.home_level.next = 0.into();
        self.alarm_level.next = 0.into();
        for i in 0..N {
            self.pos_filters[i].clock.next = self.clock.val();
            self.neg_filters[i].clock.next = self.clock.val();
            self.home_filters[i].clock.next = self.clock.val();
            self.alarm_filters[i].clock.next = self.clock.val();
            self.pos_filters[i].reset.next = self.reset.val();
            self.neg_filters[i].reset.next = self.reset.val();
            self.home_filters[i].reset.next = self.reset.val();
            self.alarm_filters[i].reset.next = self.reset.val();
            self.pos_filters[i].tick.next = self.tick.val();
            self.neg_filters[i].tick.next = self.tick.val();
            self.home_filters[i].tick.next = self.tick.val();
            self.alarm_filters[i].tick.next = self.tick.val();
            self.pos_filters[i].pin.next = self.limit_pos.val().get_bit(i);
            self.neg_filters[i].pin.next = self.limit_neg.val().get_bit(i);
            self.home_filters[i].pin.next = self.home.val().get_bit(i);
            self.alarm_filters[i].pin.next = self.alarm.val().get_bit(i);
            if self.pos_filters[i].level.val() {
                self.pos_level.next = self.pos_level.val() | self.axis_bit[i].val();
            }
            if self.neg_filters[i].level.val() {
                self.neg_level.next = self.neg_level.val() | self.axis_bit[i].val();
            }
            if self.home_filters[i].level.val() {
                self.home_level.next = self.home_level.val() | self.axis_bit[i].val();
            }
            if self.alarm_filters[i].level.val() {
                self.alarm_level.next = self.alarm_level.val() | self.axis_bit[i].val();
            }
        }
        // Polarity, then enable.
        self.pos_active.next = self.pos_level.val() ^ self.pos_ctrl.q.val().get_bits::<N>(16);
        self.neg_active.next = self.neg_level.val() ^ self.neg_ctrl.q.val().get_bits::<N>(16);
        self.home_active.next = self.home_level.val() ^ self.home_ctrl.q.val().get_bits::<N>(16);
        self.alarm_active.next = self.alarm_level.val() ^ self.alarm_ctrl.q.val().get_bits::<N>(16);
        self.home_acting.next = self.home_active.val() & self.home_ctrl.q.val().get_bits::<N>(0);
        // Causes: limits and alarms set theirs while they act, HOME at the
        // edge where it starts; a 1 written clears; the event wins.
        // (A DFF's `d` reads back its old value: the kept bits are Locals.)
        self.limit_kept.next = self.limit_cause.q.val();
        self.home_alarm_kept.next = self.home_alarm_cause.q.val();
        if self.we.val() & (self.addr.val() == self.addr_limit_cause.val()) {
            self.limit_kept.next = self.limit_cause.q.val() & !self.wdata.val();
        }
        if self.we.val() & (self.addr.val() == self.addr_home_alarm_cause.val()) {
            self.home_alarm_kept.next = self.home_alarm_cause.q.val() & !self.wdata.val();
        }
        // (bit_cast of named signals only: the exporter sizes its mask.)
        self.pos_acting.next = self.pos_active.val() & self.pos_ctrl.q.val().get_bits::<N>(0);
        self.neg_acting.next = self.neg_active.val() & self.neg_ctrl.q.val().get_bits::<N>(0);
        self.low_half.next = bit_cast::<32, N>(self.pos_acting.val());
        self.high_half.next = bit_cast::<32, N>(self.neg_acting.val());
        self.limit_events.next = self.low_half.val() | (self.high_half.val() << self.shift.val());
        self.limit_cause.d.next = self.limit_kept.val() | self.limit_events.val();
        self.home_event.next = self.home_acting.val() & !self.home_before.q.val();
        self.alarm_acting.next = self.alarm_active.val() & self.alarm_ctrl.q.val().get_bits::<N>(0);
        self.low_half.next = bit_cast::<32, N>(self.home_event.val());
        self.high_half.next = bit_cast::<32, N>(self.alarm_acting.val());
        self.home_alarm_cause.d.next = self.home_alarm_kept.val()
            | self.low_half.val()
            | (self.high_half.val() << self.shift.val());
        self.home_before.d.next = self.home_acting.val();
        if self.we.val() {
            if self.addr.val() == self.addr_pos_ctrl.val() {
                self.pos_ctrl.d.next = self.wdata.val() & self.ctrl_mask.val();
            }
            if self.addr.val() == self.addr_neg_ctrl.val() {
                self.neg_ctrl.d.next = self.wdata.val() & self.ctrl_mask.val();
            }
            if self.addr.val() == self.addr_home_ctrl.val() {
                self.home_ctrl.d.next = self.wdata.val() & self.ctrl_mask.val();
            }
            if self.addr.val() == self.addr_alarm_ctrl.val() {
                self.alarm_ctrl.d.next = self.wdata.val() & self.ctrl_mask.val();
            }
            if self.addr.val() == self.addr_limit_mask.val() {
                self.limit_mask.d.next = self.wdata.val() & self.ctrl_mask.val();
            }
            if self.addr.val() == self.addr_home_alarm_mask.val() {
                self.home_alarm_mask.d.next = self.wdata.val() & self.ctrl_mask.val();
            }
            if self.addr.val() == self.addr_home_stop.val() {
                self.home_stop.d.next = self.wdata.val().get_bits::<N>(0);
            }
        }
        self.value.next = 0.into();
        if self.read_addr.val() == self.addr_pos_ctrl.val() {
            self.value.next = self.pos_ctrl.q.val();
        }
        if self.read_addr.val() == self.addr_neg_ctrl.val() {
            self.value.next = self.neg_ctrl.q.val();
        }
        if self.read_addr.val() == self.addr_home_ctrl.val() {
            self.value.next = self.home_ctrl.q.val();
        }
        if self.read_addr.val() == self.addr_alarm_ctrl.val() {
            self.value.next = self.alarm_ctrl.q.val();
        }
        if self.read_addr.val() == self.addr_limit_inputs.val() {
            self.low_half.next = bit_cast::<32, N>(self.pos_active.val());
            self.high_half.next = bit_cast::<32, N>(self.neg_active.val());
            self.value.next = self.low_half.val() | (self.high_half.val() << self.shift.val());
        }
        if self.read_addr.val() == self.addr_home_alarm_inputs.val() {
            self.low_half.next = bit_cast::<32, N>(self.home_active.val());
            self.high_half.next = bit_cast::<32, N>(self.alarm_active.val());
            self.value.next = self.low_half.val() | (self.high_half.val() << self.shift.val());
        }
        if self.read_addr.val() == self.addr_limit_cause.val() {
            self.value.next = self.limit_cause.q.val();
        }
        if self.read_addr.val() == self.addr_limit_mask.val() {
            self.value.next = self.limit_mask.q.val();
        }
        if self.read_addr.val() == self.addr_home_alarm_cause.val() {
            self.value.next = self.home_alarm_cause.q.val();
        }
        if self.read_addr.val() == self.addr_home_alarm_mask.val() {
            self.value.next = self.home_alarm_mask.q.val();
        }
        if self.read_addr.val() == self.addr_home_stop.val() {
            self.value.next = bit_cast::<32, N>(self.home_stop.q.val());
        }
        if self.reset.val() {
            self.prescaler.d.next = 0.into();
            self.ticking.d.next = true;
            self.pos_ctrl.d.next = 0.into();
            self.neg_ctrl.d.next = 0.into();
            self.home_ctrl.d.next = 0.into();
            self.alarm_ctrl.d.next = 0.into();
            self.limit_cause.d.next = 0.into();
            self.limit_mask.d.next = 0.into();
            self.home_alarm_cause.d.next = 0.into();
            self.home_alarm_mask.d.next = 0.into();
            self.home_stop.d.next = 0.into();
            self.home_before.d.next = 0.into();
        }
        self.read_value.next = self.value.val();
        self.irq_active.next = (self.limit_cause.q.val() & self.limit_mask.q.val()).any()
            | (self.home_alarm_cause.q.val() & self.home_alarm_mask.q.val()).any();
        self.stop_both.next = self.home_alarm_cause.q.val().get_bits::<N>(16)
            | (self.home_alarm_cause.q.val().get_bits::<N>(0) & self.home_stop.q.val());
        self.stop_up.next = self.limit_cause.q.val().get_bits::<N>(0) | self.stop_both.val();
        self.stop_down.next = self.limit_cause.q.val().get_bits::<N>(16) | self.stop_both.val();
    }
}
