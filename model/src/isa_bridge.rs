//! The ISA address-counter interface and the shared 1 K × 16 RAM
//! (docs/isa_bridge.md): a transaction-level model ([`IsaCard`]: one I/O
//! read or write of one register) and a cycle-accurate, bit-accurate model of
//! the gateware ([`IsaBridgeModel`]: one FPGA clock edge at a time).

use crate::regmap::{self, ISA_ADDR_BITS, ISA_RAM_WORDS};
pub use motionhdl_spec::isa::*;

const WORDS: usize = ISA_RAM_WORDS as usize;
const ADDR_MASK: u16 = (1 << ISA_ADDR_BITS) - 1;

fn status_word(addr: u16, auto_inc: bool, wrapped: bool, collision: bool) -> u16 {
    addr | if auto_inc { status::AUTO_INC } else { 0 }
        | if wrapped { status::WRAPPED } else { 0 }
        | if collision { status::COLLISION } else { 0 }
}

/// Transaction-level model: what the PC and the DSP see, one access at a
/// time. Same-clock collisions cannot be expressed here; the cycle model has
/// them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IsaCard {
    /// Base switches: the card answers on ports `base*4 ..= base*4+3`.
    pub base: u8,
    ram: Vec<u16>,
    addr: u16,
    auto_inc: bool,
    wrapped: bool,
}

impl IsaCard {
    /// A card after reset: counter 0, AUTO_INC off, RAM all zero.
    pub fn new(base: u8) -> Self {
        assert_eq!(regmap::isa_bridge().registers.len(), 4);
        Self {
            base,
            ram: vec![0; WORDS],
            addr: 0,
            auto_inc: false,
            wrapped: false,
        }
    }

    pub fn status(&self) -> u16 {
        status_word(self.addr, self.auto_inc, self.wrapped, false)
    }
    pub fn address(&self) -> u16 {
        self.addr
    }
    pub fn ram(&self) -> &[u16] {
        &self.ram
    }

    fn advance(&mut self) {
        if self.addr == ADDR_MASK {
            self.wrapped = true;
        }
        self.addr = (self.addr + 1) & ADDR_MASK;
    }

    fn side_effects(&mut self, reg: u16) {
        match reg {
            reg::DATA if self.auto_inc => self.advance(),
            reg::ADDR_CLEAR => {
                self.addr = 0;
                self.wrapped = false;
            }
            reg::ADDR_INC => self.advance(),
            _ => {}
        }
    }

    /// An I/O write cycle (OUT) to `port`. Returns whether the card answered.
    pub fn io_write(&mut self, port: u16, aen: bool, data: u16) -> bool {
        if !selected(port, aen, self.base) {
            return false;
        }
        let reg = port & 3;
        match reg {
            reg::DATA => self.ram[usize::from(self.addr)] = data,
            reg::STATUS => {
                self.addr = data & status::ADDR_MASK;
                self.auto_inc = data & status::AUTO_INC != 0;
                if data & status::WRAPPED != 0 {
                    self.wrapped = false;
                }
            }
            _ => {}
        }
        self.side_effects(reg);
        true
    }

    /// An I/O read cycle (IN) from `port`: `None` when the card does not
    /// answer (it leaves SD undriven).
    pub fn io_read(&mut self, port: u16, aen: bool) -> Option<u16> {
        if !selected(port, aen, self.base) {
            return None;
        }
        let reg = port & 3;
        let value = match reg {
            reg::DATA => self.ram[usize::from(self.addr)],
            _ => self.status(),
        };
        self.side_effects(reg);
        Some(value)
    }

    /// The DSP side writes one word through its own port.
    pub fn dsp_write(&mut self, addr: u16, data: u16) {
        self.ram[usize::from(addr & ADDR_MASK)] = data;
    }
    /// The DSP side reads one word.
    pub fn dsp_read(&self, addr: u16) -> u16 {
        self.ram[usize::from(addr & ADDR_MASK)]
    }
}

/// Every input pin of the bridge at one sampling instant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IsaPins {
    /// SA9..SA0.
    pub sa: u16,
    /// SD15..SD0 as the bus drives them.
    pub sd_in: u16,
    pub ior_n: bool,
    pub iow_n: bool,
    pub aen: bool,
    pub bale: bool,
    /// Base-address switches.
    pub base: u8,
    /// DSP port: word address.
    pub dsp_addr: u16,
    /// DSP port: write data.
    pub dsp_wdata: u16,
    /// DSP port: write this clock.
    pub dsp_we: bool,
}

impl IsaPins {
    /// The bus idle: no command, no BALE, AEN low.
    pub fn idle(base: u8) -> Self {
        Self {
            ior_n: true,
            iow_n: true,
            base,
            ..Default::default()
        }
    }
}

/// Every output of the bridge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IsaOutputs {
    pub sd_out: u16,
    /// Drive SD15..SD0 with `sd_out`.
    pub sd_oe: bool,
    /// IOCS16#, open collector: 0 = pull low.
    pub iocs16_n: bool,
    /// DSP port read data: the word at the `dsp_addr` of the previous edge.
    pub dsp_rdata: u16,
}

/// What a RAM back-end tells the bus core in one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RamFeedback {
    /// The RAM word at the address counter, as the back-end reads it.
    pub word: u16,
    /// `word` is valid this clock (the prefetch only takes valid words).
    pub word_valid: bool,
    /// The queued PC write is done at this edge.
    pub write_done: bool,
    /// The DSP wrote the queued PC write's word at this edge.
    pub collision: bool,
}

/// Cycle-accurate model of `isa_bus_core`: decode, synchronisers, the
/// address counter, STATUS, the one-entry PC write queue and the read
/// prefetch; every flop, updated at each rising edge from the pins sampled
/// at that edge. Field names follow the HDL.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct IsaCoreModel {
    ior_s: [bool; 3],
    iow_s: [bool; 3],
    bale_s: [bool; 2],
    sel_s: [bool; 2],
    reg_s: [u16; 2],
    sd_s1: u16,
    cyc_sel: bool,
    cyc_reg: u16,
    wdata: u16,
    counter: u16,
    auto_inc: bool,
    wrapped: bool,
    collision: bool,
    pw_valid: bool,
    pw_addr: u16,
    pw_data: u16,
    data_q: u16,
    /// `data_q` holds a word the back-end called valid.
    fresh: bool,
}

impl IsaCoreModel {
    /// Power-up state: every flop 0, as rust-hdl's DFFs and the exported
    /// Verilog start.
    pub fn new() -> Self {
        Self::default()
    }
    pub fn counter(&self) -> u16 {
        self.counter
    }
    pub fn status(&self) -> u16 {
        status_word(self.counter, self.auto_inc, self.wrapped, self.collision)
    }
    /// A PC write is queued: (address, data).
    pub fn queued_write(&self) -> Option<(u16, u16)> {
        self.pw_valid.then_some((self.pw_addr, self.pw_data))
    }

    /// The bus outputs now: combinational from the pins and the flops.
    pub fn outputs(&self, pins: &IsaPins) -> (u16, bool, bool) {
        let sel = selected(pins.sa, pins.aen, pins.base);
        let sd_out = if pins.sa & 3 == reg::DATA {
            self.data_q
        } else {
            self.status()
        };
        (sd_out, sel && !pins.ior_n, !sel)
    }

    /// One rising clock edge with synchronous `reset`.
    pub fn clock(&mut self, pins: &IsaPins, reset: bool, ram: &RamFeedback) {
        let s = self.clone();
        let read_end = s.ior_s[1] && !s.ior_s[2] && s.cyc_sel;
        let write_end = s.iow_s[1] && !s.iow_s[2] && s.cyc_sel;
        let access_end = read_end || write_end;
        let reg = s.cyc_reg;

        self.ior_s = [pins.ior_n, s.ior_s[0], s.ior_s[1]];
        self.iow_s = [pins.iow_n, s.iow_s[0], s.iow_s[1]];
        self.bale_s = [pins.bale, s.bale_s[0]];
        self.sel_s = [selected(pins.sa, pins.aen, pins.base), s.sel_s[0]];
        self.reg_s = [pins.sa & 3, s.reg_s[0]];
        self.sd_s1 = pins.sd_in;
        if s.bale_s[1] {
            self.cyc_sel = s.sel_s[1];
            self.cyc_reg = s.reg_s[1];
        }
        if !s.iow_s[0] && !s.iow_s[1] {
            self.wdata = s.sd_s1;
        }

        let advance = access_end && (reg == reg::ADDR_INC || (reg == reg::DATA && s.auto_inc));
        if write_end && reg == reg::STATUS {
            self.counter = s.wdata & ADDR_MASK;
            self.auto_inc = s.wdata & status::AUTO_INC != 0;
        } else if access_end && reg == reg::ADDR_CLEAR {
            self.counter = 0;
        } else if advance {
            self.counter = (s.counter + 1) & ADDR_MASK;
        }
        let wrap = advance && s.counter == ADDR_MASK;
        let clear_wrapped = (access_end && reg == reg::ADDR_CLEAR)
            || (write_end && reg == reg::STATUS && s.wdata & status::WRAPPED != 0);
        if wrap {
            self.wrapped = true;
        } else if clear_wrapped {
            self.wrapped = false;
        }
        if ram.collision {
            self.collision = true;
        } else if write_end && reg == reg::STATUS && s.wdata & status::COLLISION != 0 {
            self.collision = false;
        }
        if write_end && reg == reg::DATA {
            self.pw_valid = true;
            self.pw_addr = s.counter;
            self.pw_data = s.wdata;
        } else if ram.write_done {
            self.pw_valid = false;
        }
        // The prefetch follows the RAM. While the PC reads this card it
        // holds, once it holds a valid word, so SD changes at most once
        // under IOR# (from stale to valid, early in a slow back-end's case).
        let frozen = s.cyc_sel && !s.ior_s[1] && s.fresh;
        if !frozen {
            if ram.word_valid {
                self.data_q = ram.word;
            }
            self.fresh = ram.word_valid;
        }

        if reset {
            self.ior_s = [true; 3];
            self.iow_s = [true; 3];
            self.bale_s = [false; 2];
            self.sel_s = [false; 2];
            self.cyc_sel = false;
            self.counter = 0;
            self.auto_inc = false;
            self.wrapped = false;
            self.collision = false;
            self.pw_valid = false;
        }
    }
}

/// Cycle-accurate model of `isa_bridge` with the RAM inside the FPGA: the
/// bus core, two RAM copies written together (one read port each) and the
/// DSP port.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IsaBridgeModel {
    core: IsaCoreModel,
    /// The PC copy's read register: the word at the counter.
    isa_rd: u16,
    dsp_rdata: u16,
    ram: Vec<u16>,
}

impl Default for IsaBridgeModel {
    fn default() -> Self {
        Self::new()
    }
}

impl IsaBridgeModel {
    /// Power-up state: every flop 0, RAM all zero (block RAM loads zeros).
    pub fn new() -> Self {
        Self {
            core: IsaCoreModel::new(),
            isa_rd: 0,
            dsp_rdata: 0,
            ram: vec![0; WORDS],
        }
    }
    pub fn core(&self) -> &IsaCoreModel {
        &self.core
    }
    pub fn counter(&self) -> u16 {
        self.core.counter()
    }
    pub fn status(&self) -> u16 {
        self.core.status()
    }
    pub fn ram(&self) -> &[u16] {
        &self.ram
    }
    /// A PC write is waiting for a clock in which the DSP port does not write.
    pub fn write_pending(&self) -> bool {
        self.core.queued_write().is_some()
    }

    /// The outputs now: combinational from the pins and the flops.
    pub fn outputs(&self, pins: &IsaPins) -> IsaOutputs {
        let (sd_out, sd_oe, iocs16_n) = self.core.outputs(pins);
        IsaOutputs {
            sd_out,
            sd_oe,
            iocs16_n,
            dsp_rdata: self.dsp_rdata,
        }
    }

    /// One rising clock edge with synchronous `reset`.
    pub fn clock(&mut self, pins: &IsaPins, reset: bool) {
        let queued = self.core.queued_write();
        let dsp_addr = pins.dsp_addr & ADDR_MASK;
        // The RAM's one write port: the DSP first, a queued PC write in the
        // first clock the DSP leaves free.
        let feedback = RamFeedback {
            word: self.isa_rd,
            word_valid: true,
            write_done: queued.is_some() && !pins.dsp_we,
            collision: pins.dsp_we && queued.is_some_and(|(a, _)| a == dsp_addr),
        };
        let counter = self.core.counter();
        self.core.clock(pins, reset, &feedback);
        // Both read ports read before this edge's write lands.
        self.isa_rd = self.ram[usize::from(counter)];
        self.dsp_rdata = self.ram[usize::from(dsp_addr)];
        if pins.dsp_we {
            self.ram[usize::from(dsp_addr)] = pins.dsp_wdata;
        } else if let Some((a, d)) = queued {
            self.ram[usize::from(a)] = d;
        }
    }
}

/// The pins between the FPGA and an external dual-port SRAM's left port.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SramPins {
    pub addr: u16,
    pub d_out: u16,
    /// The FPGA drives the data pins.
    pub d_oe: bool,
    pub ce_n: bool,
    pub oe_n: bool,
    pub we_n: bool,
}

/// Cycle-accurate model of `isa_bridge` built for an external dual-port
/// SRAM (IDT7025-style, the DSP on its other port): the bus core and the
/// sequencer driving the left port. Reads: CE#/OE# low, the address is the
/// counter, the data pins are sampled every clock and taken once the
/// address has been stable [`SRAM_READ_SETTLE_CLOCKS`]. A queued PC write:
/// one clock of address/data set-up with OE# high, WE# low for two clocks,
/// one clock of hold, all from flops.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct IsaBridgeExternalModel {
    core: IsaCoreModel,
    state: u8,
    pins: SramPins,
    sample: u16,
    stable: u8,
}

impl IsaBridgeExternalModel {
    pub fn new() -> Self {
        Self {
            pins: SramPins {
                ce_n: false,
                oe_n: false,
                we_n: true,
                ..Default::default()
            },
            ..Default::default()
        }
    }
    pub fn core(&self) -> &IsaCoreModel {
        &self.core
    }
    pub fn counter(&self) -> u16 {
        self.core.counter()
    }
    /// The SRAM pins now (all from flops).
    pub fn sram(&self) -> SramPins {
        self.pins
    }
    /// The bus outputs: (sd_out, sd_oe, iocs16_n).
    pub fn outputs(&self, pins: &IsaPins) -> (u16, bool, bool) {
        self.core.outputs(pins)
    }

    /// The prefetch takes the data sampled at the previous edge at the next
    /// edge.
    pub fn takes_sample(&self) -> bool {
        self.state == sram_state::READ
            && self.stable >= SRAM_READ_SETTLE_CLOCKS
            && self.core.queued_write().is_none()
    }

    /// One rising edge; `ram_d_in` is what the data pins show at it.
    pub fn clock(&mut self, pins: &IsaPins, reset: bool, ram_d_in: u16) {
        use sram_state::*;
        let s = self.clone();
        let queued = s.core.queued_write();
        let feedback = RamFeedback {
            word: s.sample,
            word_valid: s.takes_sample(),
            write_done: s.state == HOLD,
            collision: false,
        };
        // The read address is the counter as it was before this edge.
        let read_addr = s.core.counter();
        self.core.clock(pins, reset, &feedback);
        self.sample = ram_d_in;
        let mut next = s.pins;
        let state = match s.state {
            READ if queued.is_some() => SETUP,
            READ => READ,
            SETUP => PULSE1,
            PULSE1 => PULSE2,
            PULSE2 => HOLD,
            _ => READ,
        };
        match state {
            READ => {
                next = SramPins {
                    addr: read_addr,
                    d_out: s.pins.d_out,
                    d_oe: false,
                    ce_n: false,
                    oe_n: false,
                    we_n: true,
                };
            }
            SETUP => {
                let (a, d) = queued.expect("a queued write");
                next = SramPins {
                    addr: a,
                    d_out: d,
                    d_oe: true,
                    ce_n: false,
                    oe_n: true,
                    we_n: true,
                };
            }
            PULSE1 | PULSE2 => next.we_n = false,
            _ => next.we_n = true,
        }
        // Count clocks the read address has been on the pins.
        self.stable = if state == READ && s.state == READ && next.addr == s.pins.addr {
            s.stable.saturating_add(1).min(SRAM_READ_SETTLE_CLOCKS)
        } else {
            0
        };
        self.state = state;
        self.pins = next;
        if reset {
            self.state = READ;
            self.stable = 0;
            self.pins.d_oe = false;
            self.pins.we_n = true;
            self.pins.oe_n = false;
            self.pins.ce_n = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn register_numbers_follow_the_map() {
        let map = regmap::isa_bridge();
        for (name, n) in [
            ("DATA", reg::DATA),
            ("ADDR_CLEAR", reg::ADDR_CLEAR),
            ("ADDR_INC", reg::ADDR_INC),
            ("STATUS", reg::STATUS),
        ] {
            assert_eq!(map.register(name).offset, u32::from(n), "{name}");
        }
        let st = map.register("STATUS");
        assert_eq!(st.field("ADDR").mask(), u32::from(status::ADDR_MASK));
        assert_eq!(st.field("AUTO_INC").mask(), u32::from(status::AUTO_INC));
        assert_eq!(st.field("WRAPPED").mask(), u32::from(status::WRAPPED));
        assert_eq!(st.field("COLLISION").mask(), u32::from(status::COLLISION));
    }

    #[test]
    fn seed_sequence_clear_then_write_and_increment() {
        let mut c = IsaCard::new(0x80);
        let b = |r| port(0x80, r);
        assert!(c.io_write(b(reg::ADDR_CLEAR), false, 0));
        for i in 0..4 {
            c.io_write(b(reg::DATA), false, 100 + i);
            c.io_write(b(reg::ADDR_INC), false, 0);
        }
        assert_eq!(&c.ram()[..4], &[100, 101, 102, 103]);
        assert_eq!(c.io_read(b(reg::STATUS), false), Some(4));
        // DMA cycles and other cards' ports change nothing.
        assert!(!c.io_write(b(reg::DATA), true, 7));
        assert!(!c.io_write(port(0x81, reg::DATA), false, 7));
        assert_eq!(c.io_read(b(reg::DATA), true), None);
        assert_eq!(c.ram()[4], 0);
    }

    #[test]
    fn counter_wraps_and_status_shows_it() {
        let mut c = IsaCard::new(1);
        c.io_write(port(1, reg::STATUS), false, 0x3ff | status::AUTO_INC);
        c.io_write(port(1, reg::DATA), false, 9);
        assert_eq!(c.ram()[1023], 9);
        assert_eq!(
            c.io_read(port(1, reg::STATUS), false),
            Some(status::AUTO_INC | status::WRAPPED)
        );
        c.io_read(port(1, reg::ADDR_CLEAR), false);
        assert_eq!(c.status(), status::AUTO_INC);
    }
}
