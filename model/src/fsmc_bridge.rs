//! The STM32F4 FSMC bridge (docs/fsmc_bridge.md): the MCU's asynchronous
//! SRAM-style bus (bank 1, NE1, mode 1, 16-bit, non-multiplexed) turned into
//! transactions on a 32-bit register port and a 16-bit RAM port.
//!
//! * [`stm32f4_timing`] (from the spec): the FSMC_BTR1 values this gateware
//!   needs;
//! * [`FsmcTransactions`]: the transaction-level view (16- and 32-bit reads
//!   and writes, the tear-free 32-bit register rule);
//! * [`FsmcBridgeModel`]: the cycle-accurate, bit-accurate model of the
//!   gateware, one FPGA clock edge at a time (field names follow the HDL).

pub use motionhdl_spec::fsmc::*;

/// Transaction-level model of the bridge: what each FSMC access does to
/// the slave and returns, with the two hold registers.
///
/// * Register read, low half (A0 = 0): one register read; returns bits
///   15:0 and keeps bits 31:16 for the next access.
/// * Register read, high half (A0 = 1): if the access just before was the
///   low-half read of the same register, returns the kept half (no second
///   read: a 32-bit read is one sample); otherwise (a lone high-half read)
///   one fresh register read, returning its bits 31:16.
/// * Register write, low half: kept, nothing written. High half: one
///   32-bit write of {high, last low half written} (a lone high-half write
///   uses whatever low half was written last).
/// * RAM window: one RAM word per access.
///
/// Any access other than that high-half read drops the kept read half.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FsmcTransactions {
    hold_lo: u16,
    /// (register word, bits 31:16) of the last access, if it was a
    /// low-half register read.
    hold: Option<(u16, u16)>,
}

impl FsmcTransactions {
    /// After reset: nothing kept (the written low half is 0 at power-up and
    /// not touched by reset).
    pub fn new() -> Self {
        Self::default()
    }

    /// A synchronous reset of the bridge: the kept read half is dropped;
    /// the kept write half is not a reset flop and stays.
    pub fn reset(&mut self) {
        self.hold = None;
    }

    /// A 16-bit read at halfword address `a`.
    pub fn read16(&mut self, s: &mut impl FsmcSlave, a: u16) -> u16 {
        let a = a & ADDR_MASK;
        let hold = self.hold.take();
        if is_ram(a) {
            return s.ram_read(ram_word(a));
        }
        let word = reg_word(a);
        if a & 1 == 0 {
            let v = s.reg_read(word);
            self.hold = Some((word, (v >> 16) as u16));
            v as u16
        } else {
            match hold {
                Some((w, hi)) if w == word => hi,
                _ => (s.reg_read(word) >> 16) as u16,
            }
        }
    }

    /// A 16-bit write at halfword address `a`.
    pub fn write16(&mut self, s: &mut impl FsmcSlave, a: u16, data: u16) {
        let a = a & ADDR_MASK;
        self.hold = None;
        if is_ram(a) {
            s.ram_write(ram_word(a), data);
        } else if a & 1 == 0 {
            self.hold_lo = data;
        } else {
            s.reg_write(
                reg_word(a),
                (u32::from(data) << 16) | u32::from(self.hold_lo),
            );
        }
    }

    /// A 32-bit read at even halfword address `a`: the FSMC's two 16-bit
    /// accesses, low half first.
    pub fn read32(&mut self, s: &mut impl FsmcSlave, a: u16) -> u32 {
        assert_eq!(a & 1, 0, "32-bit accesses are word aligned");
        let lo = self.read16(s, a);
        let hi = self.read16(s, a + 1);
        (u32::from(hi) << 16) | u32::from(lo)
    }

    /// A 32-bit write at even halfword address `a`, low half first.
    pub fn write32(&mut self, s: &mut impl FsmcSlave, a: u16, data: u32) {
        assert_eq!(a & 1, 0, "32-bit accesses are word aligned");
        self.write16(s, a, data as u16);
        self.write16(s, a + 1, (data >> 16) as u16);
    }
}

/// A plain slave: a register file and a RAM, for the transaction model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlainSlave {
    pub regs: Vec<u32>,
    pub ram: Vec<u16>,
    /// Register reads done, in order (word addresses).
    pub reads: Vec<u16>,
}

impl Default for PlainSlave {
    fn default() -> Self {
        Self::new()
    }
}

impl PlainSlave {
    pub fn new() -> Self {
        Self {
            regs: vec![0; REG_WORDS as usize],
            ram: vec![0; RAM_WORDS as usize],
            reads: Vec::new(),
        }
    }
}

impl FsmcSlave for PlainSlave {
    fn reg_read(&mut self, word: u16) -> u32 {
        self.reads.push(word);
        self.regs[usize::from(word)]
    }
    fn reg_write(&mut self, word: u16, value: u32) {
        self.regs[usize::from(word)] = value;
    }
    fn ram_read(&mut self, addr: u16) -> u16 {
        self.ram[usize::from(addr)]
    }
    fn ram_write(&mut self, addr: u16, value: u16) {
        self.ram[usize::from(addr)] = value;
    }
}

// ---------------------------------------------------------------------------
// Cycle level
// ---------------------------------------------------------------------------

/// The FSMC pins at one sampling instant (all asynchronous to the FPGA).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FsmcPins {
    pub ne_n: bool,
    pub noe_n: bool,
    pub nwe_n: bool,
    /// A[11:0], halfword address.
    pub a: u16,
    /// D[15:0] as the MCU drives them.
    pub d_in: u16,
}

impl FsmcPins {
    /// The bus idle: NE1#, NOE#, NWE# high.
    pub fn idle() -> Self {
        Self {
            ne_n: true,
            noe_n: true,
            nwe_n: true,
            a: 0,
            d_in: 0,
        }
    }
}

impl Default for FsmcPins {
    fn default() -> Self {
        Self::idle()
    }
}

/// Every output of the bridge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FsmcOutputs {
    pub d_out: u16,
    /// Drive D with `d_out` (NE1# and NOE# low, from the pins).
    pub d_oe: bool,
    pub reg_addr: u16,
    pub reg_wdata: u32,
    pub reg_we: bool,
    pub reg_re: bool,
    pub ram_addr: u16,
    pub ram_wdata: u16,
    pub ram_we: bool,
}

/// Cycle-accurate model of `fsmc_bridge`: every flop, updated at each
/// rising edge from the pins and the slave's read data at that edge.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FsmcBridgeModel {
    ne_s1: bool,
    noe_s: [bool; 3],
    nwe_s: [bool; 3],
    a_s1: u16,
    d_s: [u16; 2],
    /// The access's NE1# (as "selected") and address: follow the pins two
    /// edges behind while both synchronised strobes are high, frozen while
    /// one is low.
    cyc_sel: bool,
    cyc_a: u16,
    wdata: u16,
    hold_lo: u16,
    hold_hi: u16,
    hold_word: u16,
    hold_valid: bool,
    rd_p: [bool; 2],
    rd_src: [u8; 2],
    d_q: u16,
}

impl FsmcBridgeModel {
    /// Power-up state: every flop 0, as rust-hdl's DFFs and the exported
    /// Verilog start.
    pub fn new() -> Self {
        Self::default()
    }

    fn rd_start(&self) -> bool {
        !self.noe_s[1] && self.noe_s[2] && self.cyc_sel
    }
    fn wr_end(&self) -> bool {
        self.nwe_s[1] && !self.nwe_s[2] && self.cyc_sel
    }
    fn use_hold(&self) -> bool {
        self.cyc_a & 1 != 0 && self.hold_valid && self.hold_word == reg_word(self.cyc_a)
    }
    fn cyc_ram(&self) -> bool {
        is_ram(self.cyc_a)
    }

    /// The outputs now: combinational from the pins and the flops.
    pub fn outputs(&self, pins: &FsmcPins) -> FsmcOutputs {
        let rd = self.rd_start();
        let wr = self.wr_end();
        let reg = !self.cyc_ram();
        FsmcOutputs {
            d_out: self.d_q,
            d_oe: !pins.ne_n && !pins.noe_n,
            reg_addr: reg_word(self.cyc_a),
            reg_wdata: (u32::from(self.wdata) << 16) | u32::from(self.hold_lo),
            reg_we: wr && reg && self.cyc_a & 1 != 0,
            reg_re: rd && reg && !self.use_hold(),
            ram_addr: ram_word(self.cyc_a),
            ram_wdata: self.wdata,
            ram_we: wr && !reg,
        }
    }

    /// A read is under way inside the bridge (between its start and the
    /// edge that loads `d_out`).
    pub fn read_pending(&self) -> bool {
        self.rd_start() || self.rd_p[0] || self.rd_p[1]
    }

    /// The kept high half of the last low-half register read, if valid:
    /// (register word, bits 31:16).
    pub fn hold(&self) -> Option<(u16, u16)> {
        self.hold_valid.then_some((self.hold_word, self.hold_hi))
    }

    /// One rising clock edge with synchronous `reset`; `reg_rdata` and
    /// `ram_rdata` are the slave's outputs at this edge.
    pub fn clock(&mut self, pins: &FsmcPins, reset: bool, reg_rdata: u32, ram_rdata: u16) {
        let s = self.clone();
        let rd = s.rd_start();
        let wr = s.wr_end();
        let reg = !s.cyc_ram();

        self.ne_s1 = pins.ne_n;
        self.noe_s = [pins.noe_n, s.noe_s[0], s.noe_s[1]];
        self.nwe_s = [pins.nwe_n, s.nwe_s[0], s.nwe_s[1]];
        self.a_s1 = pins.a & ADDR_MASK;
        self.d_s = [pins.d_in, s.d_s[0]];
        if s.noe_s[1] && s.nwe_s[1] {
            self.cyc_sel = !s.ne_s1;
            self.cyc_a = s.a_s1;
        }
        // D sampled while NWE# had been low at two edges in a row.
        if !s.nwe_s[1] && !s.nwe_s[2] {
            self.wdata = s.d_s[1];
        }
        if wr && reg && s.cyc_a & 1 == 0 {
            self.hold_lo = s.wdata;
        }
        // Read pipeline: start, register port address, register data, d_out.
        self.rd_p = [rd, s.rd_p[0]];
        let src = if !reg {
            read_source::RAM
        } else if s.cyc_a & 1 == 0 {
            read_source::REG_LOW
        } else if s.use_hold() {
            read_source::HOLD
        } else {
            read_source::REG_HIGH
        };
        if rd {
            self.rd_src[0] = src;
            self.hold_word = reg_word(s.cyc_a);
        }
        self.rd_src[1] = s.rd_src[0];
        if rd || wr {
            self.hold_valid = false;
        }
        if s.rd_p[1] {
            self.d_q = match s.rd_src[1] {
                read_source::RAM => ram_rdata,
                read_source::REG_LOW => reg_rdata as u16,
                read_source::REG_HIGH => (reg_rdata >> 16) as u16,
                _ => s.hold_hi,
            };
            if s.rd_src[1] == read_source::REG_LOW {
                self.hold_hi = (reg_rdata >> 16) as u16;
                self.hold_valid = true;
            }
        }

        if reset {
            self.ne_s1 = true;
            self.noe_s = [true; 3];
            self.nwe_s = [true; 3];
            self.cyc_sel = false;
            self.hold_valid = false;
            self.rd_p = [false; 2];
        }
    }
}

#[cfg(test)]
mod cycle_tests;
#[cfg(test)]
mod transaction_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timing_at_50_and_168_mhz() {
        let b = stm32f4_budget(50_000_000, 168_000_000);
        assert_eq!(
            b.timing,
            FsmcTiming {
                addset: 4,
                datast: 21,
                busturn: 0
            }
        );
        assert_eq!(b.timing.btr(), 0x0000_1504);
        // Faster FPGA clock, shorter data phase.
        let f = stm32f4_timing(100_000_000, 168_000_000);
        assert!(f.datast < 21 && f.addset < 4, "{f:?}");
    }

    #[test]
    fn thirty_two_bit_reads_are_one_sample() {
        let mut s = PlainSlave::new();
        let mut t = FsmcTransactions::new();
        s.regs[5] = 0x1234_5678;
        assert_eq!(t.read32(&mut s, 10), 0x1234_5678);
        assert_eq!(s.reads, [5]);
        // A lone high half reads afresh.
        s.regs[5] = 0xabcd_0000;
        assert_eq!(t.read16(&mut s, 11), 0xabcd);
        assert_eq!(s.reads, [5, 5]);
        t.write32(&mut s, 12, 0xdead_beef);
        assert_eq!(s.regs[6], 0xdead_beef);
        // The RAM window: one word per access.
        t.write32(&mut s, 0x800 | 6, 0x5555_aaaa);
        assert_eq!(&s.ram[6..8], &[0xaaaa, 0x5555]);
        assert_eq!(t.read16(&mut s, 0x807), 0x5555);
    }
}
