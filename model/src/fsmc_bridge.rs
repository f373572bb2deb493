//! The STM32F4 FSMC bridge (docs/fsmc_bridge.md): the MCU's asynchronous
//! SRAM-style bus (bank 1, NE1, mode 1, 16-bit, non-multiplexed) turned into
//! transactions on a 32-bit register port and a 16-bit RAM port.
//!
//! * [`stm32f4_timing`]: the FSMC_BTR1 values this gateware needs, derived
//!   from its synchroniser and read latency and the pad margins below;
//! * [`FsmcTransactions`]: the transaction-level view (16- and 32-bit reads
//!   and writes, the tear-free 32-bit register rule);
//! * [`FsmcBridgeModel`]: the cycle-accurate, bit-accurate model of the
//!   gateware, one FPGA clock edge at a time (field names follow the HDL).

use crate::regmap::MCU_HALFWORD_ADDRESS_BITS;

/// Halfword address bits A[11:0] (an 8 KB window).
pub const ADDRESS_BITS: u32 = MCU_HALFWORD_ADDRESS_BITS;
/// A11: 0 = registers, 1 = the RAM window.
pub const RAM_WINDOW_BIT: u32 = 11;
/// 32-bit registers the register port addresses (A[10:1]).
pub const REG_WORDS: u32 = 1 << 10;
/// 16-bit words in the RAM window (A[9:0]).
pub const RAM_WORDS: u32 = 1 << 10;

const ADDR_MASK: u16 = (1 << ADDRESS_BITS) - 1;

/// Is halfword address `a` in the RAM window?
pub fn is_ram(a: u16) -> bool {
    a & (1 << RAM_WINDOW_BIT) != 0
}
/// The register port's word address of halfword address `a` (A[10:1]).
pub fn reg_word(a: u16) -> u16 {
    (a >> 1) & 0x3ff
}
/// The RAM port's word address of halfword address `a` (A[9:0]).
pub fn ram_word(a: u16) -> u16 {
    a & 0x3ff
}

// ---------------------------------------------------------------------------
// Timing
// ---------------------------------------------------------------------------

/// FPGA clock edges from the first edge that samples NOE# low to the edge
/// that loads `d_out`: two synchroniser flops and the edge detect (edge 2
/// shows the start; `reg_re` is high until edge 3), the register port's
/// two-edge read (address at edge 3, `reg_rdata` at edge 4), `d_out` at
/// edge 5 (RAM reads and high halves from the hold take the same path).
/// The first sampling edge comes up to one period after NOE# falls, so the
/// worst case from NOE# falling to `d_out` loaded is this many periods.
pub const READ_LATENCY_CLOCKS: u32 = 5;

/// Strobe-to-flop skew and sampling window of an FSMC input: board trace,
/// FPGA input buffer and routing, and the first flop's setup/hold window.
/// A strobe level is only sure to be seen if it lasts one clock period plus
/// this.
pub const FPGA_INPUT_NS: f64 = 2.0;

/// FPGA clock edge to `d_out` valid at the MCU's pins: clock-to-out, output
/// buffer into the 30 pF the STM32F4 datasheet is characterised with, and
/// the board (iCE40 HX-class part, pessimistic).
pub const FPGA_OUTPUT_NS: f64 = 10.0;

/// STM32F4 read data setup time to NOE# rising, tsu(Data_NOE), from the
/// datasheet's asynchronous non-multiplexed SRAM read timings: the FSMC
/// samples D at the end of the DATAST phase, one HCLK before the pin rises
/// plus a few ns of input path; taken as THCLK + 4 ns (check against the
/// datasheet revision of the part fitted).
pub fn stm32f4_read_setup_ns(hclk_ns: f64) -> f64 {
    hclk_ns + 4.0
}

/// The STM32F4 drives write data this long after NWE# falls, at most
/// (tv(Data_NWE); the FSMC drives D for the whole data phase). Any value
/// below one FPGA period works: the bridge samples D one clock after it
/// first sees NWE# low.
pub const STM32F4_WRITE_DATA_DELAY_NS: f64 = 4.0;

/// Largest ADDSET (4 bits) and DATAST (8 bits; 0 is reserved) of FSMC_BTR.
pub const ADDSET_MAX: u32 = 15;
pub const DATAST_MAX: u32 = 255;

/// FSMC_BTR1 settings (mode 1, EXTMOD = 0: the same timing for reads and
/// writes; FSMC_BWTR1 is not used).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FsmcTiming {
    /// Address phase, HCLK cycles with NOE#/NWE# high.
    pub addset: u32,
    /// Data phase, HCLK cycles with the strobe low (writes add one HCLK of
    /// hold with NWE# high).
    pub datast: u32,
    /// Bus turnaround, HCLK cycles.
    pub busturn: u32,
}

impl FsmcTiming {
    /// The FSMC_BTR1 register value: ADDSET[3:0], ADDHLD[7:4] (unused in
    /// mode 1, left 0), DATAST[15:8], BUSTURN[19:16], ACCMOD = 00 (mode A
    /// bits ignored with EXTMOD = 0).
    pub fn btr(&self) -> u32 {
        self.addset | (self.datast << 8) | (self.busturn << 16)
    }
}

/// Everything [`stm32f4_timing`] computed, in ns, for the documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimingBudget {
    pub fpga_period_ns: f64,
    pub hclk_ns: f64,
    /// Worst case NOE# falling (at the FPGA) to `d_out` loaded.
    pub read_latency_ns: f64,
    /// Time `d_out` must be loaded before NOE# rises: input skew, output
    /// delay, MCU setup.
    pub read_lead_ns: f64,
    /// Shortest strobe high time the synchronisers are sure to see.
    pub strobe_high_min_ns: f64,
    /// Shortest NWE# low time for a sure write-data sample.
    pub write_low_min_ns: f64,
    pub timing: FsmcTiming,
}

fn ceil_div(ns: f64, hclk_ns: f64) -> u32 {
    // A hair of tolerance so that exact multiples do not round up.
    ((ns / hclk_ns) - 1e-9).ceil().max(0.0) as u32
}

/// HCLK of an STM32F4 at its full 168 MHz: the MCU clock the generated
/// header's FSMC settings assume.
pub const STM32F4_HCLK_HZ: u64 = 168_000_000;

/// The timing budget behind [`stm32f4_timing`]; panics where no FSMC
/// setting fits (see [`stm32f4_budget_checked`]).
pub fn stm32f4_budget(fpga_clock_hz: u64, hclk_hz: u64) -> TimingBudget {
    stm32f4_budget_checked(fpga_clock_hz, hclk_hz).unwrap_or_else(|e| panic!("{e}"))
}

/// The timing budget, or why the FSMC cannot reach the bridge at these
/// clocks (DATAST or ADDSET beyond their register fields, or the write data
/// too late for the FPGA clock).
pub fn stm32f4_budget_checked(fpga_clock_hz: u64, hclk_hz: u64) -> Result<TimingBudget, String> {
    let t = 1e9 / fpga_clock_hz as f64;
    let h = 1e9 / hclk_hz as f64;
    // Read: NOE# is low for DATAST HCLKs and the MCU samples D at its end.
    // The bridge has d_out loaded READ_LATENCY_CLOCKS periods after NOE#
    // falls (worst phase: NOE# falls just after an edge and is first seen a
    // whole period later), plus the input skew; it then needs the output
    // delay and the MCU's setup time before NOE# rises:
    //   DATAST * THCLK >= 5 T + FPGA_INPUT + FPGA_OUTPUT + tsu(Data_NOE).
    let read_latency = f64::from(READ_LATENCY_CLOCKS) * t;
    let read_lead = FPGA_INPUT_NS + FPGA_OUTPUT_NS + stm32f4_read_setup_ns(h);
    let datast_read = ceil_div(read_latency + read_lead, h);
    // Write: D is sampled one clock after NWE# is first seen low and the
    // sample is taken only while NWE# was low at two edges in a row, so
    // NWE# must span one period plus the input skew at every phase:
    //   DATAST * THCLK >= T + FPGA_INPUT (and the data delay < T).
    // Mode 1 uses one DATAST for both, so the read's governs.
    let write_low_min = t + FPGA_INPUT_NS;
    if STM32F4_WRITE_DATA_DELAY_NS >= t - FPGA_INPUT_NS {
        return Err(format!(
            "FSMC write data arrives {STM32F4_WRITE_DATA_DELAY_NS} ns after NWE# falls, \
             too late for a {t:.2} ns FPGA clock"
        ));
    }
    let datast = datast_read.max(ceil_div(write_low_min, h)).max(1);
    // Address phase. Between the two halves of a 32-bit access NE1 stays
    // low and NOE# (NWE#) is high for only ADDSET (ADDSET + 1) HCLKs; the
    // synchroniser must see it high at one edge or the two strobes merge
    // and the second access is lost:
    //   ADDSET * THCLK >= T + FPGA_INPUT.
    // It also gives the address (valid when NE1 falls) that long to settle
    // before the first edge that sees a strobe low.
    let strobe_high_min = t + FPGA_INPUT_NS;
    let addset = ceil_div(strobe_high_min, h).max(1);
    if addset > ADDSET_MAX || datast > DATAST_MAX {
        return Err(format!(
            "FSMC timing out of range at FPGA {fpga_clock_hz} Hz, HCLK {hclk_hz} Hz: \
             ADDSET {addset} (max {ADDSET_MAX}), DATAST {datast} (max {DATAST_MAX})"
        ));
    }
    // Bus turnaround: d_oe is NE1# low AND NOE# low straight from the pins,
    // so the FPGA lets go of D one output delay after NOE# rises; the FSMC
    // drives D again only in a write's data phase, >= ADDSET HCLKs later.
    if f64::from(addset) * h <= FPGA_OUTPUT_NS {
        return Err(format!(
            "ADDSET {addset} leaves no bus turnaround at HCLK {hclk_hz} Hz"
        ));
    }
    Ok(TimingBudget {
        fpga_period_ns: t,
        hclk_ns: h,
        read_latency_ns: read_latency,
        read_lead_ns: read_lead,
        strobe_high_min_ns: strobe_high_min,
        write_low_min_ns: write_low_min,
        timing: FsmcTiming {
            addset,
            datast,
            busturn: 0,
        },
    })
}

/// FSMC_BTR1 settings for this bridge with the FPGA at `fpga_clock_hz` and
/// the STM32F4 at `hclk_hz` (see [`stm32f4_budget`] for the derivation).
/// At 50 MHz / 168 MHz: ADDSET 4, DATAST 21, BUSTURN 0.
pub fn stm32f4_timing(fpga_clock_hz: u64, hclk_hz: u64) -> FsmcTiming {
    stm32f4_budget(fpga_clock_hz, hclk_hz).timing
}

// ---------------------------------------------------------------------------
// Transaction level
// ---------------------------------------------------------------------------

/// What sits behind the bridge, at transaction level.
pub trait FsmcSlave {
    /// One read of 32-bit register `word` (the register port's read).
    fn reg_read(&mut self, word: u16) -> u32;
    /// One write of 32-bit register `word`.
    fn reg_write(&mut self, word: u16, value: u32);
    /// One read of RAM word `addr`.
    fn ram_read(&mut self, addr: u16) -> u16;
    /// One write of RAM word `addr`.
    fn ram_write(&mut self, addr: u16, value: u16);
}

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

/// Where a read's data comes from (the read pipeline's tag).
pub mod read_source {
    /// The RAM port's `ram_rdata`.
    pub const RAM: u8 = 0;
    /// `reg_rdata` bits 15:0; bits 31:16 are kept.
    pub const REG_LOW: u8 = 1;
    /// `reg_rdata` bits 31:16 of a fresh read (a lone high half).
    pub const REG_HIGH: u8 = 2;
    /// The kept high half.
    pub const HOLD: u8 = 3;
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
