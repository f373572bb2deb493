//! The ISA address-counter interface and the shared 1 K × 16 RAM
//! (docs/isa_bridge.md): a transaction-level model ([`IsaCard`]: one I/O
//! read or write of one register) and a cycle-accurate, bit-accurate model of
//! the gateware ([`IsaBridgeModel`]: one FPGA clock edge at a time).

use crate::regmap::{self, ISA_ADDR_BITS, ISA_RAM_WORDS};
pub use motionhdl_spec::isa::*;

mod external;
pub use external::{IsaBridgeExternalModel, SramPins};

const WORDS: usize = ISA_RAM_WORDS as usize;
const ADDR_MASK: u16 = (1 << ISA_ADDR_BITS) - 1;

/// STATUS from the counter and the (flag, bit) pairs that are set.
fn status_word(addr: u16, flags: &[(bool, u16)]) -> u16 {
    flags
        .iter()
        .filter(|(on, _)| *on)
        .fold(addr, |word, (_, bit)| word | bit)
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
    irq_en: bool,
    bell: bool,
    /// The PC wrote the DSP's mailbox word and the DSP has not taken it.
    dsp_bell: bool,
    /// The card sees the DSP's writes (the RAM is inside the FPGA); with
    /// an external dual-port SRAM it does not, and BELL never sets.
    sees_dsp: bool,
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
            irq_en: false,
            bell: false,
            dsp_bell: false,
            sees_dsp: true,
        }
    }

    /// A card built for an external dual-port SRAM: the DSP's writes are
    /// out of its sight, so the DSP cannot ring the PC through it.
    pub fn with_external_ram(base: u8) -> Self {
        Self {
            sees_dsp: false,
            ..Self::new(base)
        }
    }

    /// A reset: every register as at power-up, the RAM kept (block RAM
    /// and the SRAM keep their contents).
    pub fn reset(&mut self) {
        let ram = std::mem::take(&mut self.ram);
        *self = Self {
            ram,
            sees_dsp: self.sees_dsp,
            ..Self::new(self.base)
        };
    }

    pub fn status(&self) -> u16 {
        status_word(
            self.addr,
            &[
                (self.irq_en, status::IRQ_EN),
                (self.auto_inc, status::AUTO_INC),
                (self.wrapped, status::WRAPPED),
                (self.bell, status::BELL),
            ],
        )
    }
    /// The card's IRQ line.
    pub fn irq(&self) -> bool {
        self.bell && self.irq_en
    }
    /// The DSP side takes its doorbell: whether the PC had rung it.
    pub fn take_dsp_bell(&mut self) -> bool {
        std::mem::take(&mut self.dsp_bell)
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
            reg::DATA => {
                self.ram[usize::from(self.addr)] = data;
                self.dsp_bell |= self.addr == mailbox::TO_DSP;
            }
            reg::STATUS => {
                self.addr = data & status::ADDR_MASK;
                self.auto_inc = data & status::AUTO_INC != 0;
                self.irq_en = data & status::IRQ_EN != 0;
                if data & status::WRAPPED != 0 {
                    self.wrapped = false;
                }
                if data & status::BELL != 0 {
                    self.bell = false;
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
            reg::DATA => {
                if self.addr == mailbox::TO_PC {
                    self.bell = false;
                }
                self.ram[usize::from(self.addr)]
            }
            _ => self.status(),
        };
        self.side_effects(reg);
        Some(value)
    }

    /// The DSP side writes one word through its own port.
    pub fn dsp_write(&mut self, addr: u16, data: u16) {
        self.ram[usize::from(addr & ADDR_MASK)] = data;
        self.bell |= self.sees_dsp && addr & ADDR_MASK == mailbox::TO_PC;
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
    /// The ISA IRQ line.
    pub irq: bool,
    /// The PC's write of the DSP mailbox word lands at this edge.
    pub bell_to_dsp: bool,
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
    /// The DSP wrote the PC's mailbox word at this edge.
    pub dsp_rang: bool,
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
    irq_en: bool,
    bell: bool,
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
        status_word(
            self.counter,
            &[
                (self.irq_en, status::IRQ_EN),
                (self.auto_inc, status::AUTO_INC),
                (self.wrapped, status::WRAPPED),
                (self.collision, status::COLLISION),
                (self.bell, status::BELL),
            ],
        )
    }
    /// The ISA IRQ line (from flops).
    pub fn irq(&self) -> bool {
        self.bell && self.irq_en
    }
    /// The PC's write of the DSP mailbox word lands with `ram` this clock.
    pub fn bell_to_dsp(&self, ram: &RamFeedback) -> bool {
        ram.write_done && self.pw_valid && self.pw_addr == mailbox::TO_DSP
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
            self.irq_en = s.wdata & status::IRQ_EN != 0;
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
        // The doorbells, IDT7130-style; a ring in the same clock wins.
        if ram.dsp_rang {
            self.bell = true;
        } else if (read_end && reg == reg::DATA && s.counter == mailbox::TO_PC)
            || (write_end && reg == reg::STATUS && s.wdata & status::BELL != 0)
        {
            self.bell = false;
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
            self.irq_en = false;
            self.bell = false;
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
            irq: self.core.irq(),
            bell_to_dsp: self.core.bell_to_dsp(&self.feedback(pins)),
        }
    }

    /// What the RAM tells the core this clock.
    fn feedback(&self, pins: &IsaPins) -> RamFeedback {
        let queued = self.core.queued_write();
        let dsp_addr = pins.dsp_addr & ADDR_MASK;
        // The RAM's one write port: the DSP first, a queued PC write in the
        // first clock the DSP leaves free.
        RamFeedback {
            word: self.isa_rd,
            word_valid: true,
            write_done: queued.is_some() && !pins.dsp_we,
            collision: pins.dsp_we && queued.is_some_and(|(a, _)| a == dsp_addr),
            dsp_rang: pins.dsp_we && dsp_addr == mailbox::TO_PC,
        }
    }

    /// One rising clock edge with synchronous `reset`.
    pub fn clock(&mut self, pins: &IsaPins, reset: bool) {
        let queued = self.core.queued_write();
        let dsp_addr = pins.dsp_addr & ADDR_MASK;
        let feedback = self.feedback(pins);
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

#[cfg(test)]
mod contract_tests;

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
        assert_eq!(st.field("IRQ_EN").mask(), u32::from(status::IRQ_EN));
        assert_eq!(st.field("BELL").mask(), u32::from(status::BELL));
    }

    #[test]
    fn doorbells_ring_through_the_mailbox_words() {
        let mut c = IsaCard::new(2);
        let b = |r| port(2, r);
        // DSP -> PC: the IRQ follows BELL only with IRQ_EN.
        c.dsp_write(mailbox::TO_PC, 0x55);
        assert_eq!(c.status(), status::BELL);
        assert!(!c.irq());
        c.io_write(b(reg::STATUS), false, status::IRQ_EN | mailbox::TO_PC);
        assert!(c.irq());
        // Reading another word leaves it; reading the mailbox answers it.
        c.io_write(b(reg::ADDR_INC), false, 0);
        c.io_read(b(reg::DATA), false);
        assert!(c.irq());
        c.io_write(b(reg::STATUS), false, status::IRQ_EN | mailbox::TO_PC);
        assert_eq!(c.io_read(b(reg::DATA), false), Some(0x55));
        assert!(!c.irq());
        assert_eq!(c.status() & status::BELL, 0);
        // A 1 written to BELL answers it too.
        c.dsp_write(mailbox::TO_PC, 0x56);
        c.io_write(b(reg::STATUS), false, status::BELL);
        assert_eq!(c.status(), 0);
        // PC -> DSP: only the mailbox word rings.
        c.io_write(
            b(reg::STATUS),
            false,
            (mailbox::TO_DSP - 1) | status::AUTO_INC,
        );
        c.io_write(b(reg::DATA), false, 1);
        assert!(!c.take_dsp_bell());
        c.io_write(b(reg::DATA), false, 2);
        assert!(c.take_dsp_bell());
        assert!(!c.take_dsp_bell());
        assert_eq!(c.dsp_read(mailbox::TO_DSP), 2);
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
