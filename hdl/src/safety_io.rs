//! The safety and I/O block: e-stop latch, watchdog, drive enables and the
//! interrupt line's causes and masks, behind the register bus
//! (docs/safety_io.md).

use crate::axis_causes::{AxisCauses, COUNTER_EVENTS, SOFT_LIMITS};
use crate::digital_io::DigitalIo;
use crate::machine_inputs::MachineStops;
use motionhdl_spec::regmap;
use motionhdl_spec::safety_io::WATCHDOG_KEY;
use motionhdl_spec::safety_io::{GPIO_INPUTS, GPIO_OUTPUTS};
use rust_hdl::prelude::*;

/// Word address bits the block decodes (`regmap::safety_io`).
pub const SAFETY_ADDRESS_BITS: usize = 7;
const A: usize = SAFETY_ADDRESS_BITS;
const GPI: usize = GPIO_INPUTS as usize;
const GPO: usize = GPIO_OUTPUTS as usize;

/// `N` axes' stop, enable and interrupt logic. Bus contract as the counter
/// bank's: a write acts at the edge where `we` is high; the edge where `re`
/// is high takes the address, the next edge loads `rdata`, which then
/// holds. Every output is a flip-flop (`irq` through an inverter, so it
/// is high, inactive, before the first reset).
#[derive(LogicBlock)]
pub struct SafetyIo<const N: usize> {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high. Reset sets the e-stop latch.
    pub reset: Signal<In, Bit>,
    /// Register bus word address.
    pub addr: Signal<In, Bits<A>>,
    /// Register bus write data.
    pub wdata: Signal<In, Bits<32>>,
    /// Write strobe.
    pub we: Signal<In, Bit>,
    /// Read strobe.
    pub re: Signal<In, Bit>,
    /// Read data, valid from the second clock edge after `re`.
    pub rdata: Signal<Out, Bits<32>>,
    /// The e-stop input (asynchronous): high = released; low, or an open
    /// wire pulled down on the board, = stop.
    pub estop_ok: Signal<In, Bit>,
    /// Per axis: the move is done (a level; its rise sets DONE_CAUSE).
    pub done: Signal<In, Bits<N>>,
    /// Per axis: the segment FIFO is at or below its low-water mark (its
    /// rise sets LOW_CAUSE).
    pub low: Signal<In, Bits<N>>,
    /// LIMIT_POS pins (asynchronous), bit i = axis i.
    pub limit_pos: Signal<In, Bits<N>>,
    /// LIMIT_NEG pins.
    pub limit_neg: Signal<In, Bits<N>>,
    /// HOME pins.
    pub home: Signal<In, Bits<N>>,
    /// Drive ALARM pins.
    pub alarm: Signal<In, Bits<N>>,
    /// Per axis: POSITION >= SOFT_MAX (the pulse bank's flip-flops).
    pub at_soft_max: Signal<In, Bits<N>>,
    /// Per axis: POSITION <= SOFT_MIN.
    pub at_soft_min: Signal<In, Bits<N>>,
    /// Per counter channel: STATUS.ERR and STATUS.SEEN (live flip-flops).
    pub counter_error: Signal<In, Bits<N>>,
    pub index_seen: Signal<In, Bits<N>>,
    /// The PC's write of the DSP mailbox word lands (a one-clock pulse from
    /// the ISA bridge): CAUSE.DOORBELL.
    pub doorbell: Signal<In, Bit>,
    /// The servo tick (the SERVO block's `tick`, one clock; tie low in a
    /// build without it): CAUSE.SERVO_TICK.
    pub servo_tick: Signal<In, Bit>,
    /// Stop every axis now: the e-stop latch or the bite flag is set.
    pub halt: Signal<Out, Bit>,
    /// Per axis: no step in the positive direction (a limit, an alarm or
    /// a home stop).
    pub stop_up: Signal<Out, Bits<N>>,
    /// Per axis: no step in the negative direction.
    pub stop_down: Signal<Out, Bits<N>>,
    /// Per axis: the enabled HOME input turns active; HOME_ALARM_CAUSE.HOME
    /// sets at this clock's edge, and the pulse and counter banks capture
    /// HOME_POSITION and HOME_COUNT at it (gates of flip-flops).
    pub home_event: Signal<Out, Bits<N>>,
    /// Drive ENABLE pins, high = enabled.
    pub drive_enable: Signal<Out, Bits<N>>,
    /// The IRQ pin (polarity from IRQ_CTRL; active low after reset).
    pub irq: Signal<Out, Bit>,
    /// General-purpose input pins (asynchronous).
    pub gpi: Signal<In, Bits<GPI>>,
    /// General-purpose outputs: the level driven while `gpo_oe` is 1.
    pub gpo_out: Signal<Out, Bits<GPO>>,
    /// General-purpose outputs: drive the pin (else release it).
    pub gpo_oe: Signal<Out, Bits<GPO>>,
    machine: MachineStops<N>,
    gpio: DigitalIo,
    soft: AxisCauses<N>,
    counter_events: AxisCauses<N>,
    estop_meta: DFF<Bit>,
    estop_sync: DFF<Bit>,
    estop_latch: DFF<Bit>,
    bitten: DFF<Bit>,
    armed: DFF<Bit>,
    timeout: DFF<Bits<32>>,
    count: DFF<Bits<32>>,
    enable: DFF<Bits<N>>,
    active_high: DFF<Bit>,
    cause: DFF<Bits<4>>,
    cause_mask: DFF<Bits<4>>,
    done_cause: DFF<Bits<N>>,
    done_mask: DFF<Bits<N>>,
    low_cause: DFF<Bits<N>>,
    low_mask: DFF<Bits<N>>,
    done_before: DFF<Bits<N>>,
    low_before: DFF<Bits<N>>,
    irq_low: DFF<Bit>,
    read_pending: DFF<Bit>,
    read_addr: DFF<Bits<A>>,
    read_data: DFF<Bits<32>>,
    addr_info: Constant<Bits<A>>,
    addr_status: Constant<Bits<A>>,
    addr_clear: Constant<Bits<A>>,
    addr_enable: Constant<Bits<A>>,
    addr_timeout: Constant<Bits<A>>,
    addr_reload: Constant<Bits<A>>,
    addr_count: Constant<Bits<A>>,
    addr_irq_ctrl: Constant<Bits<A>>,
    addr_cause: Constant<Bits<A>>,
    addr_cause_mask: Constant<Bits<A>>,
    addr_done_cause: Constant<Bits<A>>,
    addr_done_mask: Constant<Bits<A>>,
    addr_low_cause: Constant<Bits<A>>,
    addr_low_mask: Constant<Bits<A>>,
    info: Constant<Bits<32>>,
    key: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    status_input: Constant<Bits<32>>,
    status_estop: Constant<Bits<32>>,
    status_bitten: Constant<Bits<32>>,
    status_armed: Constant<Bits<32>>,
    status_irq: Constant<Bits<32>>,
    estop_cause: Constant<Bits<4>>,
    watchdog_cause: Constant<Bits<4>>,
    doorbell_cause: Constant<Bits<4>>,
    servo_tick_cause: Constant<Bits<4>>,
    write_clear: Signal<Local, Bit>,
    write_timeout: Signal<Local, Bit>,
    reload: Signal<Local, Bit>,
    bite: Signal<Local, Bit>,
    latch_next: Signal<Local, Bit>,
    bitten_next: Signal<Local, Bit>,
    halting: Signal<Local, Bit>,
    system_events: Signal<Local, Bits<4>>,
    irq_active: Signal<Local, Bit>,
    cause_kept: Signal<Local, Bits<4>>,
    done_kept: Signal<Local, Bits<N>>,
    low_kept: Signal<Local, Bits<N>>,
    read_value: Signal<Local, Bits<32>>,
}

impl<const N: usize> SafetyIo<N> {
    /// The block of `N` axes (1..=16), its machine inputs' filter ticking
    /// every `tick_clocks` clocks (`Config::filter_tick_clocks`).
    pub fn new(tick_clocks: u32) -> Self {
        assert!((1..=16).contains(&N), "axes = {N} out of range 1..=16");
        let map = regmap::safety_io(N as u32);
        assert_eq!(map.address_bits as usize, A);
        let addr = |name: &str| Constant::new((map.register(name).offset as u64).into());
        let k32 = |v: u32| Constant::new((v as u64).into());
        let status = map.register("STATUS");
        let bit32 = |f: &str| k32(status.field(f).mask());
        let cause = map.register("CAUSE");
        // The cause flip-flops hold the register's bits 3:0; CLEAR's fields
        // are tested at bits 0 and 1 below.
        assert_eq!(cause.field("ESTOP").lsb, 0);
        assert_eq!(cause.field("WATCHDOG").lsb, 1);
        assert_eq!(cause.field("DOORBELL").lsb, 2);
        assert_eq!(cause.field("SERVO_TICK").lsb, 3);
        assert_eq!(map.register("CLEAR").field("ESTOP").lsb, 0);
        assert_eq!(map.register("CLEAR").field("BITTEN").lsb, 1);
        assert_eq!(map.register("IRQ_CTRL").field("ACTIVE_HIGH").lsb, 0);
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            re: Default::default(),
            rdata: Default::default(),
            estop_ok: Default::default(),
            done: Default::default(),
            low: Default::default(),
            limit_pos: Default::default(),
            limit_neg: Default::default(),
            home: Default::default(),
            alarm: Default::default(),
            at_soft_max: Default::default(),
            at_soft_min: Default::default(),
            counter_error: Default::default(),
            doorbell: Default::default(),
            servo_tick: Default::default(),
            index_seen: Default::default(),
            halt: Default::default(),
            stop_up: Default::default(),
            stop_down: Default::default(),
            home_event: Default::default(),
            gpi: Default::default(),
            gpo_out: Default::default(),
            gpo_oe: Default::default(),
            machine: MachineStops::new(tick_clocks),
            gpio: DigitalIo::new(),
            soft: AxisCauses::new(SOFT_LIMITS),
            counter_events: AxisCauses::new(COUNTER_EVENTS),
            drive_enable: Default::default(),
            irq: Default::default(),
            estop_meta: Default::default(),
            estop_sync: Default::default(),
            estop_latch: Default::default(),
            bitten: Default::default(),
            armed: Default::default(),
            timeout: Default::default(),
            count: Default::default(),
            enable: Default::default(),
            active_high: Default::default(),
            cause: Default::default(),
            cause_mask: Default::default(),
            done_cause: Default::default(),
            done_mask: Default::default(),
            low_cause: Default::default(),
            low_mask: Default::default(),
            done_before: Default::default(),
            low_before: Default::default(),
            irq_low: Default::default(),
            read_pending: Default::default(),
            read_addr: Default::default(),
            read_data: Default::default(),
            addr_info: addr("INFO"),
            addr_status: addr("STATUS"),
            addr_clear: addr("CLEAR"),
            addr_enable: addr("ENABLE"),
            addr_timeout: addr("WDT_TIMEOUT"),
            addr_reload: addr("WDT_RELOAD"),
            addr_count: addr("WDT_COUNT"),
            addr_irq_ctrl: addr("IRQ_CTRL"),
            addr_cause: addr("CAUSE"),
            addr_cause_mask: addr("CAUSE_MASK"),
            addr_done_cause: addr("DONE_CAUSE"),
            addr_done_mask: addr("DONE_MASK"),
            addr_low_cause: addr("LOW_CAUSE"),
            addr_low_mask: addr("LOW_MASK"),
            info: k32(map.register("INFO").reset),
            key: k32(WATCHDOG_KEY),
            one: k32(1),
            status_input: bit32("ESTOP_INPUT"),
            status_estop: bit32("ESTOP"),
            status_bitten: bit32("BITTEN"),
            status_armed: bit32("ARMED"),
            status_irq: bit32("IRQ"),
            estop_cause: Constant::new(1.into()),
            watchdog_cause: Constant::new(2.into()),
            doorbell_cause: Constant::new(4.into()),
            servo_tick_cause: Constant::new(8.into()),
            write_clear: Default::default(),
            write_timeout: Default::default(),
            reload: Default::default(),
            bite: Default::default(),
            latch_next: Default::default(),
            bitten_next: Default::default(),
            halting: Default::default(),
            system_events: Default::default(),
            irq_active: Default::default(),
            cause_kept: Default::default(),
            done_kept: Default::default(),
            low_kept: Default::default(),
            read_value: Default::default(),
        }
    }
}

impl<const N: usize> SafetyIo<N> {
    /// The interrupt state, for the contract checks.
    pub fn probe(&self) -> crate::probe::SafetyRegisters {
        let word = |b: u64| b as u32;
        let (levels, input_ctrl, [limit_cause, limit_mask, home_alarm_cause, home_alarm_mask]) =
            self.machine.probe();
        crate::probe::SafetyRegisters {
            levels,
            input_ctrl,
            limit_cause,
            limit_mask,
            home_alarm_cause,
            home_alarm_mask,
            gpio: self.gpio.probe(),
            soft: self.soft.probe(),
            counter_events: self.counter_events.probe(),
            cause: word(self.cause.q.val().index() as u64),
            cause_mask: word(self.cause_mask.q.val().index() as u64),
            done_cause: word(self.done_cause.q.val().index() as u64),
            done_mask: word(self.done_mask.q.val().index() as u64),
            low_cause: word(self.low_cause.q.val().index() as u64),
            low_mask: word(self.low_mask.q.val().index() as u64),
            active_high: self.active_high.q.val(),
        }
    }
}

impl<const N: usize> Logic for SafetyIo<N> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            estop_meta,
            estop_sync,
            estop_latch,
            bitten,
            armed,
            timeout,
            count,
            enable,
            active_high,
            cause,
            cause_mask,
            done_cause,
            done_mask,
            low_cause,
            low_mask,
            done_before,
            low_before,
            irq_low,
            read_pending,
            read_addr,
            read_data
        );
        self.machine.clock.next = self.clock.val();
        self.machine.reset.next = self.reset.val();
        self.machine.addr.next = self.addr.val();
        self.machine.wdata.next = self.wdata.val();
        self.machine.we.next = self.we.val();
        self.machine.read_addr.next = self.read_addr.q.val();
        self.machine.limit_pos.next = self.limit_pos.val();
        self.machine.limit_neg.next = self.limit_neg.val();
        self.machine.home.next = self.home.val();
        self.machine.alarm.next = self.alarm.val();
        self.soft.clock.next = self.clock.val();
        self.soft.reset.next = self.reset.val();
        self.soft.addr.next = self.addr.val();
        self.soft.wdata.next = self.wdata.val();
        self.soft.we.next = self.we.val();
        self.soft.read_addr.next = self.read_addr.q.val();
        self.soft.low.next = self.at_soft_max.val();
        self.soft.high.next = self.at_soft_min.val();
        self.counter_events.clock.next = self.clock.val();
        self.counter_events.reset.next = self.reset.val();
        self.counter_events.addr.next = self.addr.val();
        self.counter_events.wdata.next = self.wdata.val();
        self.counter_events.we.next = self.we.val();
        self.counter_events.read_addr.next = self.read_addr.q.val();
        self.counter_events.low.next = self.counter_error.val();
        self.counter_events.high.next = self.index_seen.val();
        self.gpio.clock.next = self.clock.val();
        self.gpio.reset.next = self.reset.val();
        self.gpio.addr.next = self.addr.val();
        self.gpio.wdata.next = self.wdata.val();
        self.gpio.we.next = self.we.val();
        self.gpio.read_addr.next = self.read_addr.q.val();
        self.gpio.tick.next = self.machine.tick.val();
        self.gpio.gpi.next = self.gpi.val();
        self.write_clear.next = self.we.val() & (self.addr.val() == self.addr_clear.val());
        self.write_timeout.next = self.we.val() & (self.addr.val() == self.addr_timeout.val());
        // E-stop: two synchroniser stages, then the latch; a clear request
        // counts only while the synchronised input reads released.
        self.estop_meta.d.next = !self.estop_ok.val();
        self.estop_sync.d.next = self.estop_meta.q.val();
        self.latch_next.next = self.estop_sync.q.val()
            | (self.estop_latch.q.val() & !(self.write_clear.val() & self.wdata.val().get_bit(0)));
        self.estop_latch.d.next = self.latch_next.val();
        // Watchdog: TIMEOUT arms (0 disarms) and loads; the key reloads;
        // else it counts down and bites at 0.
        self.reload.next = self.we.val()
            & (self.addr.val() == self.addr_reload.val())
            & (self.wdata.val() == self.key.val())
            & self.armed.q.val();
        self.bite.next = self.armed.q.val()
            & !self.count.q.val().any()
            & !self.reload.val()
            & !self.write_timeout.val();
        self.bitten_next.next = self.bite.val()
            | (self.bitten.q.val() & !(self.write_clear.val() & self.wdata.val().get_bit(1)));
        self.bitten.d.next = self.bitten_next.val();
        if self.write_timeout.val() {
            self.timeout.d.next = self.wdata.val();
            self.count.d.next = self.wdata.val();
            self.armed.d.next = self.wdata.val().any();
        } else if self.reload.val() {
            self.count.d.next = self.timeout.q.val();
        } else if self.bite.val() {
            self.armed.d.next = false;
        } else if self.armed.q.val() {
            self.count.d.next = self.count.q.val() - self.one.val();
        }
        // Drive enables drop in the clock HALT rises, and stay off (and the
        // outputs take their safe state, in DigitalIo).
        if self.we.val() & (self.addr.val() == self.addr_enable.val()) {
            self.enable.d.next = self.wdata.val().get_bits::<N>(0);
        }
        self.halting.next = self.latch_next.val() | self.bitten_next.val();
        if self.halting.val() {
            self.enable.d.next = 0.into();
        }
        self.gpio.halting.next = self.halting.val();
        // Causes: set by their event, cleared by a 1 written; event first.
        self.system_events.next = 0.into();
        if self.estop_sync.q.val() & !self.estop_latch.q.val() {
            self.system_events.next = self.estop_cause.val();
        }
        if self.bite.val() {
            self.system_events.next = self.system_events.val() | self.watchdog_cause.val();
        }
        if self.doorbell.val() {
            self.system_events.next = self.system_events.val() | self.doorbell_cause.val();
        }
        if self.servo_tick.val() {
            self.system_events.next = self.system_events.val() | self.servo_tick_cause.val();
        }
        // (A DFF's `d` reads back its old value: the kept bits are Locals.)
        self.cause_kept.next = self.cause.q.val();
        if self.we.val() & (self.addr.val() == self.addr_cause.val()) {
            self.cause_kept.next = self.cause.q.val() & !self.wdata.val().get_bits::<4>(0);
        }
        self.done_kept.next = self.done_cause.q.val();
        if self.we.val() & (self.addr.val() == self.addr_done_cause.val()) {
            self.done_kept.next = self.done_cause.q.val() & !self.wdata.val().get_bits::<N>(0);
        }
        self.low_kept.next = self.low_cause.q.val();
        if self.we.val() & (self.addr.val() == self.addr_low_cause.val()) {
            self.low_kept.next = self.low_cause.q.val() & !self.wdata.val().get_bits::<N>(0);
        }
        self.cause.d.next = self.cause_kept.val() | self.system_events.val();
        self.done_cause.d.next =
            self.done_kept.val() | (self.done.val() & !self.done_before.q.val());
        self.low_cause.d.next = self.low_kept.val() | (self.low.val() & !self.low_before.q.val());
        self.done_before.d.next = self.done.val();
        self.low_before.d.next = self.low.val();
        if self.we.val() {
            if self.addr.val() == self.addr_cause_mask.val() {
                self.cause_mask.d.next = self.wdata.val().get_bits::<4>(0);
            }
            if self.addr.val() == self.addr_done_mask.val() {
                self.done_mask.d.next = self.wdata.val().get_bits::<N>(0);
            }
            if self.addr.val() == self.addr_low_mask.val() {
                self.low_mask.d.next = self.wdata.val().get_bits::<N>(0);
            }
            if self.addr.val() == self.addr_irq_ctrl.val() {
                self.active_high.d.next = self.wdata.val().get_bit(0);
            }
        }
        // The pin: one flip-flop after OR(cause AND mask) and the polarity.
        // The flip-flop holds "pin low", so at power-up (flip-flops 0,
        // before any reset) the pin is high: inactive for the default
        // active-low polarity.
        self.irq_active.next = (self.cause.q.val() & self.cause_mask.q.val()).any()
            | (self.done_cause.q.val() & self.done_mask.q.val()).any()
            | (self.low_cause.q.val() & self.low_mask.q.val()).any()
            | self.machine.irq_active.val()
            | self.gpio.irq_active.val()
            | self.soft.irq_active.val()
            | self.counter_events.irq_active.val();
        self.irq_low.d.next = self.irq_active.val() != self.active_high.q.val();
        // Reads: the address at the `re` edge, the value at the next.
        self.read_pending.d.next = self.re.val();
        if self.re.val() {
            self.read_addr.d.next = self.addr.val();
        }
        self.read_value.next = self.machine.read_value.val()
            | self.gpio.read_value.val()
            | self.soft.read_value.val()
            | self.counter_events.read_value.val();
        if self.read_addr.q.val() == self.addr_info.val() {
            self.read_value.next = self.info.val();
        }
        if self.read_addr.q.val() == self.addr_status.val() {
            if self.estop_sync.q.val() {
                self.read_value.next = self.status_input.val();
            }
            if self.estop_latch.q.val() {
                self.read_value.next = self.read_value.val() | self.status_estop.val();
            }
            if self.bitten.q.val() {
                self.read_value.next = self.read_value.val() | self.status_bitten.val();
            }
            if self.armed.q.val() {
                self.read_value.next = self.read_value.val() | self.status_armed.val();
            }
            if self.irq_active.val() {
                self.read_value.next = self.read_value.val() | self.status_irq.val();
            }
        }
        if self.read_addr.q.val() == self.addr_enable.val() {
            self.read_value.next = bit_cast::<32, N>(self.enable.q.val());
        }
        if self.read_addr.q.val() == self.addr_timeout.val() {
            self.read_value.next = self.timeout.q.val();
        }
        if self.read_addr.q.val() == self.addr_count.val() {
            self.read_value.next = self.count.q.val();
        }
        if self.read_addr.q.val() == self.addr_irq_ctrl.val() {
            self.read_value.next = bit_cast::<32, 1>(self.active_high.q.val().into());
        }
        if self.read_addr.q.val() == self.addr_cause.val() {
            self.read_value.next = bit_cast::<32, 4>(self.cause.q.val());
        }
        if self.read_addr.q.val() == self.addr_cause_mask.val() {
            self.read_value.next = bit_cast::<32, 4>(self.cause_mask.q.val());
        }
        if self.read_addr.q.val() == self.addr_done_cause.val() {
            self.read_value.next = bit_cast::<32, N>(self.done_cause.q.val());
        }
        if self.read_addr.q.val() == self.addr_done_mask.val() {
            self.read_value.next = bit_cast::<32, N>(self.done_mask.q.val());
        }
        if self.read_addr.q.val() == self.addr_low_cause.val() {
            self.read_value.next = bit_cast::<32, N>(self.low_cause.q.val());
        }
        if self.read_addr.q.val() == self.addr_low_mask.val() {
            self.read_value.next = bit_cast::<32, N>(self.low_mask.q.val());
        }
        if self.read_pending.q.val() {
            self.read_data.d.next = self.read_value.val();
        }
        if self.reset.val() {
            self.estop_meta.d.next = true;
            self.estop_sync.d.next = true;
            self.estop_latch.d.next = true;
            self.bitten.d.next = false;
            self.armed.d.next = false;
            self.timeout.d.next = 0.into();
            self.count.d.next = 0.into();
            self.enable.d.next = 0.into();
            self.active_high.d.next = false;
            self.cause.d.next = 0.into();
            self.cause_mask.d.next = 0.into();
            self.done_cause.d.next = 0.into();
            self.done_mask.d.next = 0.into();
            self.low_cause.d.next = 0.into();
            self.low_mask.d.next = 0.into();
            self.done_before.d.next = 0.into();
            self.low_before.d.next = 0.into();
            self.irq_low.d.next = false;
            self.read_pending.d.next = false;
            self.read_addr.d.next = 0.into();
            self.read_data.d.next = 0.into();
        }
        self.halt.next = self.estop_latch.q.val() | self.bitten.q.val();
        self.stop_up.next = self.machine.stop_up.val()
            | self.soft.stop_up.val()
            | self.counter_events.stop_up.val();
        self.stop_down.next = self.machine.stop_down.val()
            | self.soft.stop_down.val()
            | self.counter_events.stop_down.val();
        self.home_event.next = self.machine.home_event.val();
        self.drive_enable.next = self.enable.q.val();
        self.gpo_out.next = self.gpio.gpo_out.val();
        self.gpo_oe.next = self.gpio.gpo_oe.val();
        self.irq.next = !self.irq_low.q.val();
        self.rdata.next = self.read_data.q.val();
    }
}
