//! The safety and I/O block (docs/safety_io.md): e-stop latch, watchdog,
//! drive enables, interrupt causes and masks, behind the register bus
//! (`regmap::safety_io`).

use crate::axis_causes::{AxisCauses, COUNTER_EVENTS, SOFT_LIMITS};
use crate::counter::BusCycle;
use crate::digital_io::{DigitalIo, GpoPins};
use crate::machine_inputs::{MachinePins, MachineStops};
use crate::pulse_generator::{PulseBank, Stops};
use crate::regmap::{self, Block};
use motionhdl_spec::bus::mask_bits;
pub use motionhdl_spec::safety_io::{ESTOP_LATENCY, IRQ_LATENCY, WATCHDOG_KEY};

/// The pins and neighbours' signals the block sees in one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SafetyInputs {
    /// The e-stop input as the pin reads it: high = released.
    pub estop_ok: bool,
    /// Per axis: the move is done (a level; its rise is an event).
    pub done: u32,
    /// Per axis: the segment FIFO is at or below its low-water mark.
    pub low: u32,
    /// The limit, home and alarm pins.
    pub machine: MachinePins,
    /// Per axis: POSITION >= SOFT_MAX, POSITION <= SOFT_MIN (the pulse
    /// bank's flip-flops).
    pub at_soft_max: u32,
    pub at_soft_min: u32,
    /// Per counter channel: STATUS.ERR and STATUS.SEEN, live.
    pub counter_error: u32,
    pub index_seen: u32,
    /// The PC's write of the DSP mailbox word lands (ISA bridge).
    pub doorbell: bool,
    /// The SERVO block's tick (one clock).
    pub servo_tick: bool,
}

impl SafetyInputs {
    /// The e-stop chain and machine pins as given, and every axis's
    /// move-done and FIFO-low as `pulses` shows them now (how the top wires
    /// the two blocks).
    pub fn from_pulses(estop_ok: bool, machine: MachinePins, pulses: &PulseBank) -> Self {
        let (at_soft_max, at_soft_min) = pulses.soft_levels();
        let mut inputs = Self {
            estop_ok,
            done: 0,
            low: 0,
            machine,
            at_soft_max,
            at_soft_min,
            counter_error: 0,
            index_seen: 0,
            doorbell: false,
            servo_tick: false,
        };
        for i in 0..pulses.axes() {
            inputs.done |= u32::from(pulses.move_done(i)) << i;
            inputs.low |= u32::from(pulses.fifo_low(i)) << i;
        }
        inputs
    }
}

/// The block's state: every flip-flop of the HDL twin, by meaning.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SafetyIo {
    map: Block,
    axes: u32,
    machine: MachineStops,
    gpio: DigitalIo,
    soft: AxisCauses,
    counter_events: AxisCauses,
    /// The synchroniser's two stages of "the input asks for a stop".
    estop_meta: bool,
    estop_sync: bool,
    estop_latch: bool,
    bitten: bool,
    armed: bool,
    timeout: u32,
    count: u32,
    enable: u32,
    active_high: bool,
    cause: u32,
    cause_mask: u32,
    done_cause: u32,
    done_mask: u32,
    low_cause: u32,
    low_mask: u32,
    done_before: u32,
    low_before: u32,
    irq_pin: bool,
    read_pending: bool,
    read_addr: u32,
    rdata: u32,
}

impl SafetyIo {
    /// The block of `axes` axes with a machine-input filter tick every
    /// `tick_clocks` clocks, as after reset.
    pub fn new(axes: u32, tick_clocks: u32) -> Self {
        Self {
            map: regmap::safety_io(axes),
            axes,
            machine: MachineStops::new(axes, tick_clocks),
            gpio: DigitalIo::new(),
            soft: AxisCauses::new(axes, SOFT_LIMITS),
            counter_events: AxisCauses::new(axes, COUNTER_EVENTS),
            estop_meta: true,
            estop_sync: true,
            estop_latch: true,
            bitten: false,
            armed: false,
            timeout: 0,
            count: 0,
            enable: 0,
            active_high: false,
            cause: 0,
            cause_mask: 0,
            done_cause: 0,
            done_mask: 0,
            low_cause: 0,
            low_mask: 0,
            done_before: 0,
            low_before: 0,
            irq_pin: true,
            read_pending: false,
            read_addr: 0,
            rdata: 0,
        }
    }

    fn field_bit(&self, register: &str, field: &str) -> u32 {
        1 << self.map.register(register).field(field).lsb
    }

    /// Every axis halted: the e-stop latch or the bite flag is set.
    pub fn halted(&self) -> bool {
        self.estop_latch || self.bitten
    }

    /// What the block asks of the pulse bank in this clock.
    pub fn stops(&self) -> Stops {
        Stops {
            halt: self.halted(),
            up: self.stop_up(),
            down: self.stop_down(),
            home: self.home_event(),
        }
    }

    /// Per axis: the home event (the `home_event` port): the banks
    /// capture HOME_POSITION and HOME_COUNT at this edge.
    pub fn home_event(&self) -> u32 {
        self.machine.home_event()
    }

    /// Per axis: no step in the positive direction (a limit, an alarm or
    /// a home stop).
    pub fn stop_up(&self) -> u32 {
        self.machine.stop_up() | self.soft.stop_up() | self.counter_events.stop_up()
    }

    /// Per axis: no step in the negative direction (a limit, an alarm or
    /// a home stop).
    pub fn stop_down(&self) -> u32 {
        self.machine.stop_down() | self.soft.stop_down() | self.counter_events.stop_down()
    }

    /// The drive ENABLE pins.
    pub fn drive_enable(&self) -> u32 {
        self.enable
    }

    /// The general-purpose output pins.
    pub fn gpo_pins(&self) -> GpoPins {
        self.gpio.pins()
    }

    /// The IRQ pin's level.
    pub fn irq_pin(&self) -> bool {
        self.irq_pin
    }

    pub fn rdata(&self) -> u32 {
        self.rdata
    }

    fn status(&self) -> u32 {
        let bit = |name, on: bool| {
            if on {
                self.field_bit("STATUS", name)
            } else {
                0
            }
        };
        bit("ESTOP_INPUT", self.estop_sync)
            | bit("ESTOP", self.estop_latch)
            | bit("BITTEN", self.bitten)
            | bit("ARMED", self.armed)
            | bit("IRQ", self.irq_active())
    }

    /// OR(cause AND mask) over every cause register (STATUS.IRQ).
    fn irq_active(&self) -> bool {
        self.cause & self.cause_mask != 0
            || self.done_cause & self.done_mask != 0
            || self.low_cause & self.low_mask != 0
            || self.machine.irq_active()
            || self.gpio.irq_active()
            || self.soft.irq_active()
            || self.counter_events.irq_active()
    }

    /// What a read of `addr` returns now (0 where nothing is decoded).
    pub fn read_value(&self, addr: u32) -> u32 {
        let Some((_, r, _)) = self.map.decoded().into_iter().find(|d| d.0 == addr) else {
            return 0;
        };
        let parts = [
            self.machine.read(r.name),
            self.gpio.read(r.name),
            self.soft.read(r.name),
            self.counter_events.read(r.name),
        ];
        if let Some(value) = parts.into_iter().flatten().next() {
            return value;
        }
        match r.name {
            "INFO" => r.reset,
            "STATUS" => self.status(),
            "ENABLE" => self.enable,
            "WDT_TIMEOUT" => self.timeout,
            "WDT_COUNT" => self.count,
            "IRQ_CTRL" => u32::from(self.active_high),
            "CAUSE" => self.cause,
            "CAUSE_MASK" => self.cause_mask,
            "DONE_CAUSE" => self.done_cause,
            "DONE_MASK" => self.done_mask,
            "LOW_CAUSE" => self.low_cause,
            "LOW_MASK" => self.low_mask,
            "CLEAR" | "WDT_RELOAD" => 0,
            name => unreachable!("SAFETY.{name}"),
        }
    }

    /// One edge of `pulses` and this block wired as in the top: the bank
    /// takes this block's stops, this block the bank's move-done, FIFO-low
    /// and soft-limit comparisons, `pins` (the e-stop chain, the machine
    /// inputs) and the counter bank's (STATUS.ERR, STATUS.SEEN) flags, all
    /// as they stand before the edge.
    pub fn clock_with_pulses(
        &mut self,
        pulses: &mut PulseBank,
        reset: bool,
        (pulse_bus, snapshot): (&BusCycle, bool),
        bus: &BusCycle,
        (estop_ok, machine): (bool, MachinePins),
        (counter_error, index_seen, doorbell, servo_tick): (u32, u32, bool, bool),
    ) {
        let inputs = SafetyInputs {
            counter_error,
            index_seen,
            doorbell,
            servo_tick,
            ..SafetyInputs::from_pulses(estop_ok, machine, pulses)
        };
        pulses.clock_stopping(reset, pulse_bus, snapshot, &self.stops());
        self.clock(reset, bus, &inputs);
    }

    /// One rising clock edge.
    pub fn clock(&mut self, reset: bool, bus: &BusCycle, inputs: &SafetyInputs) {
        if reset {
            *self = Self::new(self.axes, self.machine.tick_clocks());
            return;
        }
        let addr = bus.addr & mask_bits(self.map.address_bits);
        let map = &self.map;
        let wrote = |name: &str| bus.writes(map, name);
        let axes = mask_bits(self.axes);
        if self.read_pending {
            self.rdata = self.read_value(self.read_addr);
        }
        self.read_pending = bus.re;
        if bus.re {
            self.read_addr = addr;
        }
        // The e-stop: the latch sets from the synchroniser's last stage and
        // clears on request only while that stage reads released.
        let estop_event = self.estop_sync && !self.estop_latch;
        let clear_estop = wrote("CLEAR") && bus.wdata & self.field_bit("CLEAR", "ESTOP") != 0;
        let latch = self.estop_sync || (self.estop_latch && !clear_estop);
        // The watchdog: a write of TIMEOUT arms (0 disarms) and loads the
        // count; the key reloads; else it counts down and bites at 0.
        let reload = wrote("WDT_RELOAD") && bus.wdata == WATCHDOG_KEY && self.armed;
        let bite = self.armed && self.count == 0 && !reload && !wrote("WDT_TIMEOUT");
        let clear_bitten = wrote("CLEAR") && bus.wdata & self.field_bit("CLEAR", "BITTEN") != 0;
        let bitten = bite || (self.bitten && !clear_bitten);
        if wrote("WDT_TIMEOUT") {
            self.timeout = bus.wdata;
            self.count = bus.wdata;
            self.armed = bus.wdata != 0;
        } else if reload {
            self.count = self.timeout;
        } else if bite {
            self.armed = false;
        } else if self.armed {
            self.count -= 1;
        }
        // Drive enables drop in the clock HALT rises, and stay off (and the
        // outputs take their safe state, in DigitalIo).
        let halting = latch || bitten;
        if halting {
            self.enable = 0;
        } else {
            self.enable = bus.written(map, "ENABLE", self.enable);
        }
        // Causes: set by their event, cleared by a 1 written, event first.
        let w1c = |name: &str, cause: u32, events: u32| (cause & !bus.cleared(map, name)) | events;
        let system_events = if estop_event {
            self.field_bit("CAUSE", "ESTOP")
        } else {
            0
        } | if bite {
            self.field_bit("CAUSE", "WATCHDOG")
        } else {
            0
        } | if inputs.doorbell {
            self.field_bit("CAUSE", "DOORBELL")
        } else {
            0
        } | if inputs.servo_tick {
            self.field_bit("CAUSE", "SERVO_TICK")
        } else {
            0
        };
        let done_events = inputs.done & !self.done_before & axes;
        let low_events = inputs.low & !self.low_before & axes;
        let cause = w1c("CAUSE", self.cause, system_events);
        let done_cause = w1c("DONE_CAUSE", self.done_cause, done_events);
        let low_cause = w1c("LOW_CAUSE", self.low_cause, low_events);
        let mask_write = |name: &str, old: u32| bus.written(map, name, old);
        // The pin: one flip-flop after this clock's causes, masks and
        // polarity.
        self.irq_pin = self.irq_active() == self.active_high;
        let tick = self.machine.tick();
        self.machine.clock(&self.map, bus, &inputs.machine);
        self.soft
            .clock(&self.map, bus, inputs.at_soft_max, inputs.at_soft_min);
        self.counter_events
            .clock(&self.map, bus, inputs.counter_error, inputs.index_seen);
        self.gpio
            .clock(&self.map, bus, tick, halting, inputs.machine.gpi);
        self.cause = cause;
        self.done_cause = done_cause;
        self.low_cause = low_cause;
        self.cause_mask = mask_write("CAUSE_MASK", self.cause_mask);
        self.done_mask = mask_write("DONE_MASK", self.done_mask);
        self.low_mask = mask_write("LOW_MASK", self.low_mask);
        if wrote("IRQ_CTRL") {
            self.active_high = bus.wdata & 1 == 1;
        }
        self.done_before = inputs.done & axes;
        self.low_before = inputs.low & axes;
        self.estop_latch = latch;
        self.bitten = bitten;
        self.estop_sync = self.estop_meta;
        self.estop_meta = !inputs.estop_ok;
    }
}

#[cfg(test)]
mod contract_tests;

#[cfg(test)]
mod tests {
    use super::*;

    fn run(block: &mut SafetyIo, bus: BusCycle, estop_ok: bool) {
        let inputs = SafetyInputs {
            estop_ok,
            ..Default::default()
        };
        block.clock(false, &bus, &inputs);
    }

    fn write(name: &str, data: u32) -> BusCycle {
        BusCycle::write(regmap::safety_io(2).register(name).offset, data)
    }

    #[test]
    fn the_estop_latch_needs_the_input_released_and_a_clear() {
        let mut b = SafetyIo::new(2, 1);
        assert!(b.halted(), "reset sets the latch");
        // Released, but the synchroniser still reads the reset's stop.
        run(&mut b, write("CLEAR", 1), true);
        assert!(b.halted());
        run(&mut b, BusCycle::default(), true);
        run(&mut b, write("CLEAR", 1), true);
        assert!(!b.halted(), "released two edges before the clear");
        run(&mut b, write("ENABLE", 3), true);
        assert_eq!(b.drive_enable(), 3);
        // Low at one edge: halted ESTOP_LATENCY edges later, counting it.
        run(&mut b, BusCycle::default(), false);
        for _ in 1..ESTOP_LATENCY - 1 {
            run(&mut b, BusCycle::default(), true);
            assert!(!b.halted());
        }
        run(&mut b, BusCycle::default(), true);
        assert!(b.halted());
        assert_eq!(b.drive_enable(), 0, "the drives drop with HALT");
        run(&mut b, write("ENABLE", 3), true);
        assert_eq!(b.drive_enable(), 0, "no enable while halted");
        run(&mut b, write("CLEAR", 1), true);
        assert!(!b.halted());
        assert_eq!(b.drive_enable(), 0, "the drives stay off after a clear");
    }

    /// A direction stop is the OR of its sources (the limit that way, an
    /// alarm, HOME with HOME_STOP, the soft limit that way): with any two or
    /// more set at once the axis still stops (a parity would free it).
    #[test]
    fn any_set_of_stop_sources_stops_the_axis() {
        // Sources as bits: 1 limit, 2 alarm, 4 home with HOME_STOP, 8 soft.
        let stops = |sources: u32, up: bool| {
            let mut b = SafetyIo::new(2, 1);
            let on = |bit: u32| u32::from(sources & bit != 0);
            let inputs = SafetyInputs {
                estop_ok: true,
                machine: MachinePins {
                    limit_pos: if up { on(1) } else { 0 },
                    limit_neg: if up { 0 } else { on(1) },
                    alarm: on(2),
                    home: on(4),
                    ..Default::default()
                },
                at_soft_max: if up { on(8) } else { 0 },
                at_soft_min: if up { 0 } else { on(8) },
                ..Default::default()
            };
            for (name, value) in [
                ("LIMIT_POS_CTRL", 1),
                ("LIMIT_NEG_CTRL", 1),
                ("ALARM_CTRL", 1),
                ("HOME_CTRL", 1),
                ("HOME_STOP", 1),
                ("SOFT_LIMIT_CTRL", 1 | 1 << 16),
            ] {
                b.clock(false, &write(name, value), &inputs);
            }
            // Two synchroniser edges and the filter's ticks, with room.
            for _ in 0..50 {
                b.clock(false, &BusCycle::default(), &inputs);
            }
            (b.stop_up() & 1 == 1, b.stop_down() & 1 == 1)
        };
        let mut cases = 0;
        for up in [true, false] {
            assert_eq!(stops(0, up), (false, false), "no source, up {up}");
            for sources in 1..16 {
                // The limit and the soft limit stop one way; the alarm
                // and the home stop both ways.
                let one_way = sources & 0b1001 != 0;
                let both_ways = sources & 0b0110 != 0;
                let expected = (both_ways || (one_way && up), both_ways || (one_way && !up));
                assert_eq!(
                    stops(sources, up),
                    expected,
                    "sources {sources:04b}, up {up}"
                );
                cases += 1;
            }
        }
        assert_eq!(cases, 30);
    }

    #[test]
    fn the_watchdog_bites_timeout_plus_one_edges_after_its_last_reload() {
        let mut b = SafetyIo::new(1, 1);
        for bus in [BusCycle::default(), write("CLEAR", 1)] {
            run(&mut b, bus, true);
            run(&mut b, bus, true);
        }
        assert!(!b.halted());
        run(&mut b, write("WDT_TIMEOUT", 5), true);
        for _ in 0..3 {
            run(&mut b, BusCycle::default(), true);
        }
        run(&mut b, write("WDT_RELOAD", WATCHDOG_KEY ^ 1), true);
        run(&mut b, write("WDT_RELOAD", WATCHDOG_KEY), true);
        for _ in 0..5 {
            run(&mut b, BusCycle::default(), true);
            assert!(!b.halted());
        }
        run(&mut b, BusCycle::default(), true);
        assert!(b.halted(), "bitten at the sixth edge after the reload");
        assert_eq!(b.cause, 2);
        run(&mut b, write("CLEAR", 2), true);
        assert!(!b.halted());
        run(&mut b, BusCycle::default(), true);
        assert!(!b.halted(), "the watchdog stays off after a bite");
    }

    #[test]
    fn the_irq_pin_follows_an_unmasked_cause_one_edge_later() {
        let mut b = SafetyIo::new(2, 1);
        let done = |b: &mut SafetyIo, done: u32, bus: BusCycle| {
            let inputs = SafetyInputs {
                estop_ok: true,
                done,
                ..Default::default()
            };
            b.clock(false, &bus, &inputs);
        };
        done(&mut b, 2, BusCycle::default());
        assert_eq!(b.done_cause, 2);
        assert!(b.irq_pin(), "masked: the active-low pin stays high");
        done(&mut b, 2, write("DONE_MASK", 2));
        assert!(b.irq_pin(), "the mask acts on the pin one edge later");
        done(&mut b, 2, BusCycle::default());
        assert!(!b.irq_pin());
        done(&mut b, 2, write("DONE_CAUSE", 2));
        done(&mut b, 2, BusCycle::default());
        assert!(
            b.irq_pin(),
            "cleared; a level that stays high is no new event"
        );
    }
}
