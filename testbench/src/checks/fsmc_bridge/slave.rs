//! The FSMC bridge's test slave: a register file with the counter bank's
//! read contract, live registers that change every clock, and a RAM with
//! the DSP-port contract; in Rust for the rust-hdl runs, and its Verilog
//! twin for the player.

use super::Counts;
use crate::player::Peripheral;
use motionhdl_model::fsmc_bridge::{self as m, FsmcOutputs};

/// Live registers: word addresses whose value changes every FPGA clock,
/// `(k & 0xffff) * 0x10001` at edge k, so both halves of one sample are
/// equal and a torn 32-bit read shows.
pub const LIVE_WORDS: std::ops::RangeInclusive<u16> = 0x3f0..=0x3ff;
/// What the test slave's `reg_rdata` shows between the edge that takes a
/// read's address and the edge that loads its data (the contract leaves it
/// undefined there).
pub const RDATA_POISON: u32 = 0xdead_beef;

/// Is `word` a live register of the test slave?
pub fn is_live(word: u16) -> bool {
    // The Verilog slave decodes them as reg_addr[9:4] == 6'h3f.
    debug_assert_eq!(LIVE_WORDS.contains(&word), word >> 4 == 0x3f);
    LIVE_WORDS.contains(&word)
}

/// The live registers' value at edge `k`.
pub fn live_value(k: u64) -> u32 {
    (k & 0xffff) as u32 * 0x1_0001
}

/// The test slave, cycle level: a register file with the counter bank's
/// read contract (the edge with `reg_re` takes the address, the next edge
/// loads `reg_rdata`; in between it shows [`RDATA_POISON`]), live
/// registers, and a RAM with the DSP-port contract (`ram_rdata` is the word
/// at the previous edge's `ram_addr`, read before that edge's write).
#[derive(Clone, Debug)]
pub struct TestSlave {
    pub regs: Vec<u32>,
    pub ram: Vec<u16>,
    read_addr: Option<u16>,
    pub rdata: u32,
    pub ram_rdata: u16,
    /// Edges so far.
    pub k: u64,
    pub counts: Counts,
}

impl Default for TestSlave {
    fn default() -> Self {
        Self::new()
    }
}

impl TestSlave {
    pub fn new() -> Self {
        Self {
            regs: vec![0; m::REG_WORDS as usize],
            ram: vec![0; m::RAM_WORDS as usize],
            read_addr: None,
            rdata: 0,
            ram_rdata: 0,
            k: 0,
            counts: Counts::default(),
        }
    }

    fn value(&self, word: u16) -> u32 {
        if is_live(word) {
            live_value(self.k)
        } else {
            self.regs[usize::from(word)]
        }
    }

    /// One rising edge; `o` are the bridge's outputs just before it.
    pub fn edge(&mut self, o: &FsmcOutputs) {
        if let Some(w) = self.read_addr.take() {
            self.rdata = self.value(w);
        } else if o.reg_re {
            self.rdata = RDATA_POISON;
        }
        if o.reg_re {
            self.read_addr = Some(o.reg_addr);
            self.counts.reg_reads += 1;
        }
        if o.reg_we {
            self.counts.reg_writes += 1;
            if !is_live(o.reg_addr) {
                self.regs[usize::from(o.reg_addr)] = o.reg_wdata;
            }
        }
        self.ram_rdata = self.ram[usize::from(o.ram_addr)];
        if o.ram_we {
            self.counts.ram_writes += 1;
            self.ram[usize::from(o.ram_addr)] = o.ram_wdata;
        }
        self.k += 1;
    }
}

/// The test slave in Verilog, the twin of [`TestSlave`], placed beside the
/// bridge by the player.
pub const TEST_SLAVE_V: &str = include_str!("../../../verilog/fsmc_test_slave.v");
/// Clocks the Verilog slave spends clearing its arrays; the bus stream
/// starts this many whole clocks late.
pub const SLAVE_CLEAR_CLOCKS: u64 = 1100;

pub(super) fn test_slave() -> Peripheral {
    // The one fact the two slaves share that the Verilog spells itself.
    assert!(
        TEST_SLAVE_V.contains(&format!("32'h{RDATA_POISON:08x}")),
        "fsmc_test_slave.v and RDATA_POISON disagree"
    );
    Peripheral::new("fsmc_test_slave", "fsmc_test_slave.v", TEST_SLAVE_V)
}
