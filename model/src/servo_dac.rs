//! The servo DAC block (docs/servo_dac.md): four staged DAC codes written
//! to a DAC7744-style parallel interface and latched together by one
//! LOADDACS rise, started by the servo tick, an UPDATE write or the safe
//! input, behind the register bus (`regmap::servo_dac`).

use crate::counter::BusCycle;
use crate::regmap::Block;
use motionhdl_spec::bus::mask_bits;
pub use motionhdl_spec::servo_dac::{
    serial_update_latency, update_latency, DAC_CHANNELS, FRAME_BITS, SAFE_CODE,
};

const CHANNELS: usize = DAC_CHANNELS as usize;

/// The DAC interface's pins as the block drives them (every one a
/// flip-flop in the HDL). R/W is always low: the block only writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DacPins {
    pub data: u32,
    /// A1:A0, the channel written.
    pub addr: u32,
    pub cs_n: bool,
    pub rw_n: bool,
    pub ldac_n: bool,
    /// The serial option's SCLK (idles high), SDIN and SYNC (active low).
    pub sclk: bool,
    pub sdin: bool,
    pub sync_n: bool,
}

/// The last SCLK half of a frame: 2 per bit.
const LAST_HALF: u32 = 2 * FRAME_BITS - 1;

/// Where a transfer is: per channel a setup clock, CS low, a hold clock;
/// then LOADDACS low.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Phase {
    Setup,
    Write,
    Hold,
    Load,
}

/// The block's state: every flip-flop of the HDL twin, by meaning.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ServoDac {
    clock_hz: u64,
    map: Block,
    period: u32,
    count: u32,
    tick: bool,
    events: u32,
    cs_low: u32,
    ldac_low: u32,
    /// SERIAL: MODE, SCLK_HALF, SYNC_HIGH.
    serial: (bool, u32, u32),
    prefix: u32,
    code: [u32; CHANNELS],
    output: [u32; CHANNELS],
    busy: bool,
    pending: bool,
    /// The codes of the running transfer, latched at its start.
    shadow: [u32; CHANNELS],
    /// The running transfer's CS_LOW and LDAC_LOW, latched at its start.
    run_cs_low: u32,
    run_ldac_low: u32,
    /// The running transfer's SERIAL and PREFIX, latched at its start.
    run_serial: (bool, u32, u32),
    run_prefix: u32,
    /// The frame being shifted (prefix and code) and its SCLK half: 0..=47.
    frame: u32,
    half: u32,
    channel: usize,
    phase: Phase,
    /// Clocks left in the phase after this one (Write and Load).
    wait: u32,
    safe: bool,
    read_pending: bool,
    read_addr: u32,
    rdata: u32,
}

/// Ordered by the flip-flops alone (the map and the clock are the
/// instance's), so the checks can enumerate the reachable states.
impl Ord for ServoDac {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.flops().cmp(&other.flops())
    }
}

impl PartialOrd for ServoDac {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

/// Every flip-flop's value, grouped: the tick, the registers, the
/// transfer, the read path.
type Flops = (
    (u32, u32, bool, u32),
    (
        u32,
        u32,
        (bool, u32, u32),
        u32,
        [u32; CHANNELS],
        [u32; CHANNELS],
    ),
    (bool, bool, [u32; CHANNELS], u32, u32, usize, Phase, u32),
    ((bool, u32, u32), u32, u32, u32),
    (bool, bool, u32, u32),
);

impl ServoDac {
    fn flops(&self) -> Flops {
        (
            (self.period, self.count, self.tick, self.events),
            (
                self.cs_low,
                self.ldac_low,
                self.serial,
                self.prefix,
                self.code,
                self.output,
            ),
            (
                self.busy,
                self.pending,
                self.shadow,
                self.run_cs_low,
                self.run_ldac_low,
                self.channel,
                self.phase,
                self.wait,
            ),
            (self.run_serial, self.run_prefix, self.frame, self.half),
            (self.safe, self.read_pending, self.read_addr, self.rdata),
        )
    }

    /// The block as reset leaves it, for a clock of `clock_hz` (TIMING's
    /// reset value). Reset asks for a transfer: the DAC is driven to the
    /// staged codes, SAFE_CODE after reset, without waiting for a tick.
    pub fn new(clock_hz: u64) -> Self {
        let map = crate::regmap::servo_dac(clock_hz);
        let timing = map.register("TIMING");
        let (cs_low, ldac_low) = (timing.field("CS_LOW").reset, timing.field("LDAC_LOW").reset);
        let serial = map.register("SERIAL");
        let serial = (
            false,
            serial.field("SCLK_HALF").reset,
            serial.field("SYNC_HIGH").reset,
        );
        let prefix = map.register("PREFIX").reset;
        Self {
            clock_hz,
            map,
            period: 0,
            count: 0,
            tick: false,
            events: 0,
            cs_low,
            ldac_low,
            serial,
            prefix,
            code: [SAFE_CODE; CHANNELS],
            output: [SAFE_CODE; CHANNELS],
            busy: false,
            pending: true,
            shadow: [SAFE_CODE; CHANNELS],
            run_cs_low: cs_low,
            run_ldac_low: ldac_low,
            run_serial: serial,
            run_prefix: prefix,
            frame: 0,
            half: 0,
            channel: 0,
            phase: Phase::Setup,
            wait: 0,
            safe: false,
            read_pending: false,
            read_addr: 0,
            rdata: 0,
        }
    }

    /// The block's register map.
    pub fn map(&self) -> &Block {
        &self.map
    }

    /// The pins as the HDL's flip-flops power up, before the first reset
    /// (the data pins at 0; the rest as after reset): for a top compared
    /// from its first clock.
    pub fn at_power_up(mut self) -> Self {
        self.shadow = [0; CHANNELS];
        self
    }

    /// The servo tick: high for one clock every TICK_PERIOD clocks. The
    /// counter bank's snapshot strobe in the top; a transfer starts at the
    /// edge that ends this clock.
    pub fn tick(&self) -> bool {
        self.tick
    }

    /// The interface's pins now.
    pub fn pins(&self) -> DacPins {
        let serial = self.run_serial.0;
        let in_frame = self.busy && serial && matches!(self.phase, Phase::Write | Phase::Hold);
        DacPins {
            data: self.shadow[self.channel],
            addr: self.channel as u32,
            cs_n: !(self.busy && !serial && self.phase == Phase::Write),
            rw_n: false,
            ldac_n: !(self.busy
                && self.phase == Phase::Load
                && (!serial || self.wait <= self.run_ldac_low)),
            sclk: !(in_frame && self.phase == Phase::Write && self.half % 2 == 1),
            sdin: self.frame >> (FRAME_BITS - 1 - self.half / 2) & 1 == 1,
            sync_n: !in_frame,
        }
    }

    /// What the DAC outputs (CH[n].OUTPUT): the codes of the last LOADDACS
    /// rise.
    pub fn outputs(&self) -> [u32; CHANNELS] {
        self.output
    }

    pub fn rdata(&self) -> u32 {
        self.rdata
    }

    fn bit(&self, register: &str, field: &str) -> u32 {
        self.map.register(register).field(field).mask()
    }

    /// What a read of `addr` returns now (0 where nothing is decoded).
    pub fn read_value(&self, addr: u32) -> u32 {
        let Some((_, r, index)) = self.map.decoded().into_iter().find(|d| d.0 == addr) else {
            return 0;
        };
        let on = |register, field, set: bool| if set { self.bit(register, field) } else { 0 };
        match (r.name, index) {
            ("INFO", None) => r.reset,
            ("STATUS", None) => {
                on("STATUS", "BUSY", self.busy)
                    | on("STATUS", "PENDING", self.pending)
                    | on("STATUS", "SAFE", self.safe)
            }
            ("EVENTS", None) => self.events,
            ("TICK_PERIOD", None) => self.period,
            ("TIMING", None) => self.cs_low | self.ldac_low << 8,
            ("SERIAL", None) => {
                let (mode, sclk_half, sync_high) = self.serial;
                u32::from(mode) | sclk_half << 8 | sync_high << 16
            }
            ("PREFIX", None) => self.prefix,
            ("CODE", Some(i)) => self.code[i as usize],
            ("OUTPUT", Some(i)) => self.output[i as usize],
            ("UPDATE", None) => 0,
            (name, _) => unreachable!("SERVO.{name}"),
        }
    }

    /// The register `bus` writes at this edge, if any.
    fn written(&self, bus: &BusCycle) -> Option<(&'static str, Option<u32>)> {
        let addr = bus.addr & mask_bits(self.map.address_bits);
        bus.we.then_some(())?;
        let (_, r, index) = self.map.decoded().into_iter().find(|d| d.0 == addr)?;
        Some((r.name, index))
    }

    /// One rising clock edge; `safe` is the e-stop / bite input.
    pub fn clock(&mut self, reset: bool, bus: &BusCycle, safe: bool) {
        if reset {
            *self = Self::new(self.clock_hz);
            return;
        }
        if self.read_pending {
            self.rdata = self.read_value(self.read_addr);
        }
        self.read_pending = bus.re;
        if bus.re {
            self.read_addr = bus.addr & mask_bits(self.map.address_bits);
        }
        let written = self.written(bus);
        let wrote = |name: &str| written.is_some_and(|(n, _)| n == name);
        // The transfer: a request (tick, UPDATE, the safe input's rise, or
        // one waiting) starts one at an edge where none runs or the running
        // one ends; else it waits, one deep.
        let ending = self.busy && self.phase == Phase::Load && self.wait == 0;
        let asked = self.tick || wrote("UPDATE") || (safe && !self.safe);
        let free = !self.busy || ending;
        let mut events_set = 0;
        if self.tick {
            events_set |= self.bit("EVENTS", "TICK");
            if !free {
                events_set |= self.bit("EVENTS", "OVERRUN");
            }
        }
        if ending {
            self.output = self.shadow;
        }
        if free && (asked || self.pending) {
            self.busy = true;
            self.pending = false;
            self.shadow = if safe {
                [SAFE_CODE; CHANNELS]
            } else {
                self.code
            };
            self.run_cs_low = self.cs_low;
            self.run_ldac_low = self.ldac_low;
            self.run_serial = self.serial;
            self.run_prefix = self.prefix;
            self.channel = 0;
            self.phase = Phase::Setup;
            self.wait = self.setup_clocks();
        } else {
            self.pending |= asked;
            if self.busy {
                self.step();
            }
        }
        // The servo tick: every PERIOD clocks; a write restarts it.
        if wrote("TICK_PERIOD") {
            self.period = bus.wdata;
            self.count = bus.wdata.saturating_sub(1);
            self.tick = false;
        } else {
            self.tick = self.period != 0 && self.count == 0;
            self.count = match (self.period, self.count) {
                (0, _) => 0,
                (p, 0) => p - 1,
                (_, c) => c - 1,
            };
        }
        // A new event wins over a clear in the same clock.
        let cleared = if wrote("EVENTS") { bus.wdata } else { 0 };
        self.events = (self.events & !cleared) | events_set;
        match written {
            Some(("TIMING", None)) => {
                self.cs_low = bus.wdata & 0xff;
                self.ldac_low = bus.wdata >> 8 & 0xff;
            }
            Some(("SERIAL", None)) => {
                let w = bus.wdata;
                self.serial = (w & 1 == 1, w >> 8 & 0xff, w >> 16 & 0xff);
            }
            Some(("PREFIX", None)) => self.prefix = bus.wdata,
            Some(("CODE", Some(i))) => self.code[i as usize] = bus.wdata & 0xffff,
            _ => {}
        }
        self.safe = safe;
    }

    /// Clocks after the first of a setup phase: SYNC's high time in the
    /// serial option (the running transfer's SERIAL).
    fn setup_clocks(&self) -> u32 {
        match self.run_serial {
            (true, _, sync_high) => sync_high,
            _ => 0,
        }
    }

    /// One edge of the running transfer.
    fn step(&mut self) {
        let (serial, sclk_half, sync_high) = self.run_serial;
        match self.phase {
            Phase::Setup if self.wait > 0 => self.wait -= 1,
            Phase::Setup if serial => {
                let prefix = self.run_prefix >> (8 * self.channel) & 0xff;
                self.frame = prefix << 16 | self.shadow[self.channel];
                self.half = 0;
                self.phase = Phase::Write;
                self.wait = sclk_half;
            }
            Phase::Setup => {
                self.phase = Phase::Write;
                self.wait = self.run_cs_low;
            }
            Phase::Write if self.wait > 0 => self.wait -= 1,
            Phase::Write if serial && self.half < LAST_HALF => {
                self.half += 1;
                self.wait = sclk_half;
            }
            Phase::Write => self.phase = Phase::Hold,
            Phase::Hold if self.channel + 1 < CHANNELS => {
                self.channel += 1;
                self.phase = Phase::Setup;
                self.wait = self.setup_clocks();
            }
            Phase::Hold => {
                self.phase = Phase::Load;
                self.wait = self.run_ldac_low + if serial { sync_high + 1 } else { 0 };
            }
            Phase::Load if self.wait > 0 => self.wait -= 1,
            Phase::Load => self.busy = false,
        }
    }
}

#[cfg(test)]
mod tests;
