//! Facts of the STM32F4 FSMC bridge (docs/fsmc_bridge.md) that the model,
//! the HDL and the firmware share: the address split, the read pipeline's
//! source encoding, and [`stm32f4_timing`], the FSMC_BTR1 values the
//! gateware needs, derived from its synchroniser and read latency and the
//! pad margins below.

use crate::regmap::MCU_HALFWORD_ADDRESS_BITS;

/// Halfword address bits A[11:0] (an 8 KB window).
pub const ADDRESS_BITS: u32 = MCU_HALFWORD_ADDRESS_BITS;
/// A11: 0 = registers, 1 = the RAM window.
pub const RAM_WINDOW_BIT: u32 = 11;
/// 32-bit registers the register port addresses (A[10:1]).
pub const REG_WORDS: u32 = 1 << 10;
/// 16-bit words in the RAM window (A[9:0]).
pub const RAM_WORDS: u32 = 1 << 10;

/// The halfword address bits that reach the bridge.
pub const ADDR_MASK: u16 = (1 << ADDRESS_BITS) - 1;

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
