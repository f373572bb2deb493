//! Checks of the FSMC bridge (docs/fsmc_bridge.md).
//!
//! One stimulus language, [`Op`], drives everything: an STM32F4 FSMC
//! bus-functional model turns each 16- or 32-bit access into the mode-1
//! waveform (ADDSET HCLKs of address phase, DATAST HCLKs of strobe, a
//! write's one HCLK of hold, NE1# low across the two halves of a 32-bit
//! access) at HCLK = 168 MHz against the 50 MHz FPGA clock, on an exact
//! time grid of 1/42 ns on which both clocks fall. The same op list runs
//! * through the rust-hdl block and the cycle model together, with a test
//!   slave (register file with the two-edge read and live registers that
//!   change every clock; RAM with the DSP-port contract): [`run_rust`];
//! * through the generated Verilog under a Verilog FSMC BFM and the same
//!   slave in Verilog, in Icarus and Verilator: [`run_verilog`];
//!
//! and every read, as the MCU samples it, is compared with the
//! transaction-level model ([`expected`]), as are the numbers of register
//! reads, register writes and RAM writes (nothing lost or doubled).

use crate::harness::{settle, CheckReport};
use crate::verilog_sim::{build_and_run, Simulator, Target};
use motionhdl_hdl::{catalog, FsmcBridge};
use motionhdl_model::fsmc_bridge::{
    self as m, FsmcBridgeModel, FsmcOutputs, FsmcPins, FsmcSlave, FsmcTiming, FsmcTransactions,
    PlainSlave,
};
use rust_hdl::prelude::*;
use std::fmt::Write as _;
use std::fs;

/// Time unit of the bus-functional models: 1/42 ns, so that the 20 ns FPGA
/// period (840) and the 168 MHz HCLK period (250) are both whole.
pub const TICKS_PER_NS: u64 = 42;
/// FPGA clock (50 MHz) and MCU clock (HCLK, 168 MHz) the checks run at.
pub const FPGA_CLOCK_HZ: u64 = 50_000_000;
pub const HCLK_HZ: u64 = 168_000_000;
/// FPGA clock period in ticks.
pub const CLOCK_TICKS: u64 = 840;
/// First rising FPGA edge (10 ns); edges follow every [`CLOCK_TICKS`].
pub const FIRST_EDGE_TICKS: u64 = 420;
/// HCLK period in ticks (5.952 ns).
pub const HCLK_TICKS: u64 = 250;
/// Distinct phases of the HCLK grid against the FPGA clock: HCLK edges sit
/// on multiples of gcd(250, 840) = 10 ticks (0.238 ns) from any FPGA edge,
/// 84 of them per period. The bus-functional model puts its grid 5 ticks
/// off those, so no bus event ever shares a time with an FPGA edge.
pub const PHASES: u32 = (CLOCK_TICKS / 10) as u32;
/// Grid offset of the MCU's events from the phase points.
const GRID: u64 = 5;
/// The write data is driven this long after NWE# falls (4 ns, pessimistic:
/// the FSMC drives it for the whole data phase).
pub const WRITE_DATA_DELAY_TICKS: u64 = 168;
/// The "end" read observation: 10 ticks (0.24 ns) before NOE# rises.
pub const END_OBSERVATION_TICKS: u64 = 10;
/// What the FPGA sees on D when the MCU does not drive it.
pub const FLOATING_BUS: u16 = 0xffff;
/// Live registers: word addresses whose value changes every FPGA clock,
/// `(k & 0xffff) * 0x10001` at edge k, so both halves of one sample are
/// equal and a torn 32-bit read shows.
pub const LIVE_WORDS: std::ops::RangeInclusive<u16> = 0x3f0..=0x3ff;
/// What the test slave's `reg_rdata` shows between the edge that takes a
/// read's address and the edge that loads its data (the contract leaves it
/// undefined there).
pub const RDATA_POISON: u32 = 0xdead_beef;

/// The timing the checks use: exactly [`m::stm32f4_timing`] at 50/168 MHz.
pub fn documented_timing() -> FsmcTiming {
    m::stm32f4_timing(FPGA_CLOCK_HZ, HCLK_HZ)
}

/// How long before NOE# rises the bridge's `d_out` must already be valid
/// in the (zero-delay) simulation: the read lead of the timing budget
/// (input skew + output delay + MCU setup), rounded up to the 10-tick grid.
pub fn read_lead_ticks() -> u64 {
    let b = m::stm32f4_budget(FPGA_CLOCK_HZ, HCLK_HZ);
    let ticks = (b.read_lead_ns * TICKS_PER_NS as f64).ceil() as u64;
    ticks.div_ceil(10) * 10
}

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

/// One step of stimulus. Addresses are FSMC halfword addresses A[11:0].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// One 16-bit read (an LDRH).
    Read16 { a: u16 },
    /// One 16-bit write (an STRH).
    Write16 { a: u16, data: u16 },
    /// A 32-bit read (an LDR at even `a`): two accesses, NE1# low across.
    Read32 { a: u16 },
    /// A 32-bit write (an STR at even `a`).
    Write32 { a: u16, data: u32 },
    /// A 16-bit access to another bank: the strobes move, NE1# stays high.
    Other { write: bool, a: u16, data: u16 },
    /// NE1# high for this many more HCLKs.
    Idle { hclk: u16 },
    /// Wait for the next FPGA rising edge, then put the HCLK grid at phase
    /// point `phase` (0..84) after it.
    Align { phase: u16 },
    /// Synchronous reset for 5 clocks, starting at the first falling edge
    /// 4 clocks after the last access (the slave keeps its contents).
    Reset,
}

/// What one read observed (at the MCU's pins as the bridge drives them):
/// `d_oe`/`d_out` the read lead before NOE# rises and just before it rises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Observation {
    pub oe_setup: bool,
    pub oe_end: bool,
    pub data_setup: u16,
    pub data_end: u16,
}

/// What a read must observe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expect {
    /// Driven with this value, stable from the setup point.
    Data(u16),
    /// A live register's half: any value, stable.
    Live,
    /// The high half of a live 32-bit sample: equal to the last live half
    /// observed (the two halves of one sample are equal).
    LiveHigh,
    /// Another bank's read: not driven.
    NotDriven,
}

/// Register reads, register writes and RAM writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub reg_reads: u64,
    pub reg_writes: u64,
    pub ram_writes: u64,
}

/// The transaction model's slave: a plain register file and RAM (live
/// registers read as 0 and ignore writes), counting transactions.
struct TbSlave {
    plain: PlainSlave,
    counts: Counts,
    live_read: bool,
}

impl FsmcSlave for TbSlave {
    fn reg_read(&mut self, word: u16) -> u32 {
        self.counts.reg_reads += 1;
        if is_live(word) {
            self.live_read = true;
            0
        } else {
            self.plain.reg_read(word)
        }
    }
    fn reg_write(&mut self, word: u16, value: u32) {
        self.counts.reg_writes += 1;
        if !is_live(word) {
            self.plain.reg_write(word, value);
        }
    }
    fn ram_read(&mut self, addr: u16) -> u16 {
        self.plain.ram_read(addr)
    }
    fn ram_write(&mut self, addr: u16, value: u16) {
        self.counts.ram_writes += 1;
        self.plain.ram_write(addr, value);
    }
}

/// What the transaction model says every read observes, and the counts.
pub fn expected(ops: &[Op]) -> (Vec<Expect>, Counts) {
    let mut t = FsmcTransactions::new();
    let mut s = TbSlave {
        plain: PlainSlave::new(),
        counts: Counts::default(),
        live_read: false,
    };
    let mut out = Vec::new();
    let read = |t: &mut FsmcTransactions, s: &mut TbSlave, a: u16, out: &mut Vec<Expect>| {
        s.live_read = false;
        let v = t.read16(s, a);
        let live = !m::is_ram(a) && is_live(m::reg_word(a));
        out.push(if !live {
            Expect::Data(v)
        } else if a & 1 == 1 && !s.live_read {
            Expect::LiveHigh
        } else {
            Expect::Live
        });
    };
    for op in ops {
        match *op {
            Op::Read16 { a } => read(&mut t, &mut s, a, &mut out),
            Op::Read32 { a } => {
                read(&mut t, &mut s, a, &mut out);
                read(&mut t, &mut s, a + 1, &mut out);
            }
            Op::Write16 { a, data } => t.write16(&mut s, a, data),
            Op::Write32 { a, data } => t.write32(&mut s, a, data),
            Op::Other { write, .. } => {
                if !write {
                    out.push(Expect::NotDriven);
                }
            }
            Op::Idle { .. } | Op::Align { .. } => {}
            Op::Reset => t.reset(),
        }
    }
    (out, s.counts)
}

/// Does `got` satisfy `want`? `last_live` carries the last live half.
fn satisfies(got: &Observation, want: &Expect, last_live: &mut Option<u16>) -> bool {
    let driven = got.oe_setup && got.oe_end && got.data_setup == got.data_end;
    match *want {
        Expect::Data(v) => driven && got.data_end == v,
        Expect::Live => {
            *last_live = Some(got.data_end);
            driven
        }
        Expect::LiveHigh => driven && Some(got.data_end) == *last_live,
        Expect::NotDriven => !got.oe_setup && !got.oe_end,
    }
}

/// A pin change at a time, or an observation point.
#[derive(Clone, Copy, Debug)]
pub enum Event {
    /// The pins and the reset input from now on.
    Pins(FsmcPins, bool),
    /// Sample `d_oe`/`d_out` the read lead before NOE# rises.
    ObserveSetup,
    /// Sample them again just before NOE# rises.
    ObserveEnd,
}

fn next_rising(t: u64) -> u64 {
    if t < FIRST_EDGE_TICKS {
        FIRST_EDGE_TICKS
    } else {
        FIRST_EDGE_TICKS + ((t - FIRST_EDGE_TICKS) / CLOCK_TICKS + 1) * CLOCK_TICKS
    }
}

fn next_falling(t: u64) -> u64 {
    (t / CLOCK_TICKS + 1) * CLOCK_TICKS
}

/// The STM32F4 bus-functional model: every op as timed pin changes
/// (ticks). Returns the events and the end time.
pub fn timeline(ops: &[Op], timing: &FsmcTiming) -> (Vec<(u64, Event)>, u64) {
    let h = HCLK_TICKS;
    let lead = read_lead_ticks();
    let mut pins = FsmcPins::idle();
    pins.d_in = FLOATING_BUS;
    let mut reset = false;
    let mut t: u64 = GRID;
    let mut ev: Vec<(u64, Event)> = vec![(0, Event::Pins(pins, reset))];
    for op in ops {
        let (ours, write, accesses): (bool, bool, Vec<(u16, u16)>) = match *op {
            Op::Read16 { a } => (true, false, vec![(a, 0)]),
            Op::Write16 { a, data } => (true, true, vec![(a, data)]),
            Op::Read32 { a } => (true, false, vec![(a, 0), (a + 1, 0)]),
            Op::Write32 { a, data } => (
                true,
                true,
                vec![(a, data as u16), (a + 1, (data >> 16) as u16)],
            ),
            Op::Other { write, a, data } => (false, write, vec![(a, data)]),
            Op::Idle { hclk } => {
                t += u64::from(hclk) * h;
                continue;
            }
            Op::Align { phase } => {
                assert!(u32::from(phase) < PHASES);
                t = next_rising(t) + GRID + 10 * u64::from(phase);
                continue;
            }
            Op::Reset => {
                // Four clocks after the last access: its action is done.
                t = next_falling(t + 4 * CLOCK_TICKS);
                reset = true;
                ev.push((t, Event::Pins(pins, reset)));
                t += 5 * CLOCK_TICKS;
                reset = false;
                ev.push((t, Event::Pins(pins, reset)));
                t += GRID;
                continue;
            }
        };
        assert!(timing.datast >= 1 && u64::from(timing.datast) * h > lead + END_OBSERVATION_TICKS);
        pins.ne_n = !ours;
        for (a, data) in accesses {
            // Address phase: A (and, for a write, not yet the data).
            pins.a = a & 0xfff;
            if write {
                pins.d_in = !data;
            }
            ev.push((t, Event::Pins(pins, reset)));
            let fall = t + u64::from(timing.addset) * h;
            let rise = fall + u64::from(timing.datast) * h;
            if write {
                pins.nwe_n = false;
                ev.push((fall, Event::Pins(pins, reset)));
                pins.d_in = data;
                ev.push((fall + WRITE_DATA_DELAY_TICKS, Event::Pins(pins, reset)));
                pins.nwe_n = true;
                ev.push((rise, Event::Pins(pins, reset)));
                // One HCLK of hold with NWE# high, then the next access.
                t = rise + h;
            } else {
                pins.noe_n = false;
                ev.push((fall, Event::Pins(pins, reset)));
                ev.push((rise - lead, Event::ObserveSetup));
                ev.push((rise - END_OBSERVATION_TICKS, Event::ObserveEnd));
                pins.noe_n = true;
                ev.push((rise, Event::Pins(pins, reset)));
                t = rise;
            }
        }
        pins.ne_n = true;
        pins.d_in = FLOATING_BUS;
        ev.push((t, Event::Pins(pins, reset)));
        t += (1 + u64::from(timing.busturn)) * h;
    }
    // Events at one time stay in push order.
    ev.sort_by_key(|e| e.0);
    (ev, t + 8 * CLOCK_TICKS)
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

/// The rust-hdl block, the cycle model and the test slave stepped through
/// `ops`.
pub struct RustRun {
    /// What the reads observed (from the HDL).
    pub observations: Vec<Observation>,
    /// Clock edges simulated.
    pub clocks: u64,
    /// HDL/model disagreements (first few), with the time.
    pub mismatches: Vec<String>,
    pub counts: Counts,
}

fn set_pins(uut: &mut FsmcBridge, p: &FsmcPins, reset: bool) {
    uut.ne_n.next = p.ne_n;
    uut.noe_n.next = p.noe_n;
    uut.nwe_n.next = p.nwe_n;
    uut.a.next = u64::from(p.a).into();
    uut.d_in.next = u64::from(p.d_in).into();
    uut.reset.next = reset;
}

fn hdl_outputs(uut: &FsmcBridge) -> FsmcOutputs {
    FsmcOutputs {
        d_out: uut.d_out.val().index() as u16,
        d_oe: uut.d_oe.val(),
        reg_addr: uut.reg_addr.val().index() as u16,
        reg_wdata: uut.reg_wdata.val().index() as u32,
        reg_we: uut.reg_we.val(),
        reg_re: uut.reg_re.val(),
        ram_addr: uut.ram_addr.val().index() as u16,
        ram_wdata: uut.ram_wdata.val().index() as u16,
        ram_we: uut.ram_we.val(),
    }
}

/// Runs `ops` with `timing` through the rust-hdl block and the cycle model
/// (every output compared before every edge and at every observation),
/// with the test slave behind both.
pub fn run_rust(ops: &[Op], timing: &FsmcTiming) -> RustRun {
    let (events, end) = timeline(ops, timing);
    let mut uut = FsmcBridge::new();
    uut.connect_all();
    let mut model = FsmcBridgeModel::new();
    let mut slave = TestSlave::new();
    let mut pins = FsmcPins::idle();
    let mut reset = false;
    let mut run = RustRun {
        observations: Vec::new(),
        clocks: 0,
        mismatches: Vec::new(),
        counts: Counts::default(),
    };
    let mismatch = |run: &mut RustRun, s: String| {
        if run.mismatches.len() < 10 {
            run.mismatches.push(s);
        }
    };
    let mut pending: Option<(bool, u16)> = None;
    let mut edge = FIRST_EDGE_TICKS;
    let mut i = 0;
    let observe = |uut: &mut FsmcBridge, pins: &FsmcPins, reset: bool| {
        set_pins(uut, pins, reset);
        settle(uut);
        hdl_outputs(uut)
    };
    while edge <= end || i < events.len() {
        while i < events.len() && events[i].0 < edge {
            let (t, e) = events[i];
            match e {
                Event::Pins(p, r) => {
                    pins = p;
                    reset = r;
                }
                Event::ObserveSetup | Event::ObserveEnd => {
                    let o = observe(&mut uut, &pins, reset);
                    let mo = model.outputs(&pins);
                    if o != mo {
                        mismatch(&mut run, format!("t={t}: outputs HDL {o:?} model {mo:?}"));
                    }
                    if matches!(e, Event::ObserveSetup) {
                        pending = Some((o.d_oe, o.d_out));
                    } else {
                        let (oe_setup, data_setup) = pending.take().expect("setup first");
                        run.observations.push(Observation {
                            oe_setup,
                            oe_end: o.d_oe,
                            data_setup,
                            data_end: o.d_out,
                        });
                    }
                }
            }
            assert_ne!(t, edge, "an event at a clock edge");
            i += 1;
        }
        if edge > end {
            break;
        }
        let o = observe(&mut uut, &pins, reset);
        let mo = model.outputs(&pins);
        if o != mo {
            let k = run.clocks;
            mismatch(
                &mut run,
                format!("t={edge} before edge {k}: HDL {o:?} model {mo:?}"),
            );
        }
        let (rdata, ram_rdata) = (slave.rdata, slave.ram_rdata);
        uut.clock.next = Clock::from(true);
        settle(&mut uut);
        uut.clock.next = Clock::from(false);
        settle(&mut uut);
        model.clock(&pins, reset, rdata, ram_rdata);
        slave.edge(&o);
        uut.reg_rdata.next = u64::from(slave.rdata).into();
        uut.ram_rdata.next = u64::from(slave.ram_rdata).into();
        run.clocks += 1;
        edge += CLOCK_TICKS;
    }
    run.counts = slave.counts;
    run
}

/// Compares observations and counts with the transaction model: one case
/// per read, plus one for the counts.
fn compare(r: &mut CheckReport, got: &[Observation], counts: Counts, ops: &[Op]) {
    let (want, want_counts) = expected(ops);
    if got.len() != want.len() {
        r.failures.push(format!(
            "{} reads observed, {} expected",
            got.len(),
            want.len()
        ));
        return;
    }
    let mut last_live = None;
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        let ok = satisfies(g, w, &mut last_live);
        r.case((!ok).then(|| format!("read #{k}: observed {g:?}, expected {w:?}")));
    }
    r.case((counts != want_counts).then(|| {
        format!("slave saw {counts:?}, transaction model {want_counts:?} (lost or doubled)")
    }));
}

/// Cases of [`phase_sweep_ops`] per phase.
pub const SWEEP_CASES_PER_PHASE: u64 = 12;
/// Cases of the phase sweep: [`PHASES`] × [`SWEEP_CASES_PER_PHASE`].
pub const SWEEP_CASES: u64 = PHASES as u64 * SWEEP_CASES_PER_PHASE;

/// Register and RAM addresses the sweep uses.
const W_A: u16 = 0x0a5;
const W_B: u16 = 0x15a;
const W_C: u16 = 0x2c3;
const LIVE: u16 = 0x3f7;
const RAM: u16 = 0x800;

fn reg_a(word: u16) -> u16 {
    word << 1
}

/// Every case at every one of the 84 phases of the HCLK grid against the
/// FPGA clock, each case aligned to the phase and its transactions back to
/// back (NE1# high for 1 + BUSTURN HCLKs between them). Returns the ops and
/// the number of cases.
pub fn phase_sweep_ops() -> (Vec<Op>, u64) {
    let mut ops = vec![Op::Reset];
    let mut cases = 0;
    for phase in 0..PHASES as u16 {
        let p = u32::from(phase);
        let d = |k: u32| 0x1000_0001u32.wrapping_mul(p * 16 + k + 1) ^ 0xa5c3_3c5a;
        let case: [Vec<Op>; SWEEP_CASES_PER_PHASE as usize] = [
            // 32-bit register write then read back.
            vec![
                Op::Write32 {
                    a: reg_a(W_A),
                    data: d(0),
                },
                Op::Read32 { a: reg_a(W_A) },
            ],
            // A live register read as 32 bits: one sample.
            vec![Op::Read32 { a: reg_a(LIVE) }],
            // The halves as separate transactions: the hold still serves.
            vec![
                Op::Read16 { a: reg_a(W_A) },
                Op::Read16 { a: reg_a(W_A) + 1 },
            ],
            // A lone high half reads afresh.
            vec![Op::Read16 { a: reg_a(W_B) + 1 }],
            // The halves of a write as separate transactions.
            vec![
                Op::Write16 {
                    a: reg_a(W_B),
                    data: d(1) as u16,
                },
                Op::Write16 {
                    a: reg_a(W_B) + 1,
                    data: (d(1) >> 16) as u16,
                },
                Op::Read32 { a: reg_a(W_B) },
            ],
            // RAM: 16-bit write and read.
            vec![
                Op::Write16 {
                    a: RAM | (phase * 7 % 1024),
                    data: d(2) as u16,
                },
                Op::Read16 {
                    a: RAM | (phase * 7 % 1024),
                },
            ],
            // RAM: 32-bit write, two words; read back as 32 and 16 bits.
            vec![
                Op::Write32 {
                    a: RAM | 0x200,
                    data: d(3),
                },
                Op::Read32 { a: RAM | 0x200 },
                Op::Read16 { a: RAM | 0x201 },
            ],
            // Another bank's cycles change nothing and are not answered.
            vec![
                Op::Other {
                    write: true,
                    a: reg_a(W_A) + 1,
                    data: 0x0bad,
                },
                Op::Other {
                    write: false,
                    a: reg_a(W_A),
                    data: 0,
                },
                Op::Read32 { a: reg_a(W_A) },
            ],
            // A lone high half of a live register.
            vec![Op::Read16 { a: reg_a(LIVE) + 1 }],
            // Write then read of another word straight after (no idle).
            vec![
                Op::Write32 {
                    a: reg_a(W_C),
                    data: !d(4),
                },
                Op::Read32 { a: reg_a(W_C) },
                Op::Read32 { a: reg_a(W_A) },
            ],
            // A low-half read of one word, then the high half of another:
            // the hold must not serve it.
            vec![
                Op::Read16 { a: reg_a(W_A) },
                Op::Read16 { a: reg_a(W_C) + 1 },
            ],
            // RAM then registers back to back, 16-bit reads of RAM words.
            vec![
                Op::Read16 { a: RAM | 0x200 },
                Op::Read32 { a: reg_a(W_B) },
                Op::Read16 {
                    a: RAM | (phase * 7 % 1024),
                },
            ],
        ];
        for c in case {
            ops.push(Op::Align { phase });
            ops.extend(c);
            cases += 1;
        }
    }
    (ops, cases)
}

/// Runs `ops` in the rust-hdl block with `timing`; `cases` is the number
/// of cases the ops make (the report covers one per read and one for the
/// counts).
pub fn check_rust(name: &str, ops: &[Op], timing: &FsmcTiming) -> (CheckReport, RustRun) {
    let (want, _) = expected(ops);
    let mut r = CheckReport::new(
        "fsmc_bridge",
        &format!(
            "{name}: rust-hdl vs cycle model every clock, reads and counts vs transaction model \
             ({timing:?})"
        ),
        want.len() as u64 + 1,
    );
    let run = run_rust(ops, timing);
    r.failures.extend(run.mismatches.iter().cloned());
    compare(&mut r, &run.observations, run.counts, ops);
    (r, run)
}

/// The phase sweep in rust-hdl with `timing`. Returns the report and the
/// number of sweep cases.
pub fn sweep_rust(timing: &FsmcTiming) -> (CheckReport, u64) {
    let (ops, cases) = phase_sweep_ops();
    assert_eq!(cases, SWEEP_CASES);
    (check_rust("phase sweep", &ops, timing).0, cases)
}

/// Phases (of the 84) at which some read of the sweep fails with `timing`:
/// each phase's cases run on their own.
pub fn failing_phases(timing: &FsmcTiming) -> Vec<u16> {
    let (ops, _) = phase_sweep_ops();
    // Split at the phase boundaries (every case starts with an Align).
    let mut by_phase: Vec<Vec<Op>> = vec![Vec::new(); PHASES as usize];
    for op in ops.iter().skip(1) {
        if let Op::Align { phase } = op {
            by_phase[usize::from(*phase)].push(*op);
        } else {
            let last = by_phase.iter_mut().rev().find(|v| !v.is_empty()).unwrap();
            last.push(*op);
        }
    }
    by_phase
        .into_iter()
        .enumerate()
        .filter_map(|(p, body)| {
            let mut v = vec![Op::Reset];
            v.extend(body);
            let (r, _) = check_rust("phase", &v, timing);
            (!r.failures.is_empty()).then_some(p as u16)
        })
        .collect()
}

/// Phases (of the 84) at which one lone 16-bit register read (after a
/// 32-bit write of a known value) returns wrong data with `timing`.
pub fn read_failing_phases(timing: &FsmcTiming) -> Vec<u16> {
    (0..PHASES as u16)
        .filter(|&phase| {
            let ops = [
                Op::Reset,
                Op::Write32 {
                    a: reg_a(W_A),
                    data: 0x1234_5678 ^ u32::from(phase),
                },
                Op::Align { phase },
                Op::Read16 { a: reg_a(W_A) },
            ];
            let (r, _) = check_rust("lone read", &ops, timing);
            !r.failures.is_empty()
        })
        .collect()
}

pub use crate::harness::Rng;

/// Random traffic: 16- and 32-bit reads and writes of a few registers
/// (so reads meet earlier writes), live registers, RAM words, other banks'
/// cycles, random idle times and phases, an occasional reset.
pub fn random_ops(seed: u64, n: usize) -> Vec<Op> {
    let mut rng = Rng::new(seed);
    let mut ops = vec![Op::Reset];
    for _ in 0..n {
        let reg = |rng: &mut Rng| -> u16 {
            match rng.below(8) {
                0 => *LIVE_WORDS.start() + rng.below(16) as u16,
                1 => rng.below(1024) as u16,
                _ => rng.below(6) as u16 * 0x45,
            }
        };
        let ram = |rng: &mut Rng| -> u16 {
            RAM | if rng.below(2) == 0 {
                rng.below(8) as u16
            } else {
                rng.below(1024) as u16
            }
        };
        match rng.below(20) {
            0..=3 => ops.push(Op::Read32 {
                a: reg_a(reg(&mut rng)),
            }),
            4..=6 => ops.push(Op::Write32 {
                a: reg_a(reg(&mut rng)),
                data: rng.next_u64() as u32,
            }),
            7..=8 => ops.push(Op::Read16 {
                a: reg_a(reg(&mut rng)) | rng.below(2) as u16,
            }),
            9 => ops.push(Op::Write16 {
                a: reg_a(reg(&mut rng)) | rng.below(2) as u16,
                data: rng.next_u64() as u16,
            }),
            10..=11 => ops.push(Op::Read16 { a: ram(&mut rng) }),
            12..=13 => ops.push(Op::Write16 {
                a: ram(&mut rng),
                data: rng.next_u64() as u16,
            }),
            14 => {
                let a = ram(&mut rng) & !1;
                ops.push(if rng.below(2) == 0 {
                    Op::Read32 { a }
                } else {
                    Op::Write32 {
                        a,
                        data: rng.next_u64() as u32,
                    }
                });
            }
            15 => ops.push(Op::Other {
                write: rng.below(2) == 0,
                a: rng.below(4096) as u16,
                data: rng.next_u64() as u16,
            }),
            16 => ops.push(Op::Idle {
                hclk: rng.below(12) as u16,
            }),
            17..=18 => ops.push(Op::Align {
                phase: rng.below(u64::from(PHASES)) as u16,
            }),
            _ => {
                if rng.below(8) == 0 {
                    ops.push(Op::Reset);
                } else {
                    ops.push(Op::Read32 {
                        a: reg_a(rng.below(6) as u16 * 0x45),
                    });
                }
            }
        }
    }
    ops
}

/// Seed and length of the long random run that goes through every simulator.
pub const LONG_RANDOM: (u64, usize) = (0xf53c_b1d6, 1500);

// ---------------------------------------------------------------------------
// Verilog
// ---------------------------------------------------------------------------

/// One op as a 64-bit word of `ops.hex` for the Verilog BFM.
pub fn encode(op: &Op) -> u64 {
    let f = |kind: u64, a: u16, data: u32, param: u16| {
        (kind << 60) | (u64::from(a & 0xfff) << 48) | (u64::from(data) << 16) | u64::from(param)
    };
    match *op {
        Op::Read16 { a } => f(1, a, 0, 0),
        Op::Write16 { a, data } => f(2, a, u32::from(data), 0),
        Op::Read32 { a } => f(3, a, 0, 0),
        Op::Write32 { a, data } => f(4, a, data, 0),
        Op::Other { write, a, data } => f(if write { 6 } else { 5 }, a, u32::from(data), 0),
        Op::Idle { hclk } => f(7, 0, 0, hclk),
        Op::Align { phase } => f(8, 0, 0, phase),
        Op::Reset => f(9, 0, 0, 0),
    }
}

/// The Verilog FSMC bus-functional model, test slave and testbench: reads
/// the ops from `ops.hex`, prints one `RD` line per read and the slave's
/// counts. Same waveform and time grid as [`timeline`].
pub fn verilog_testbench(timing: &FsmcTiming, ops: usize) -> String {
    fsmc_bfm_verilog(
        timing,
        ops,
        "fsmc_bfm_tb",
        "fsmc_bridge and its test slave",
        &test_slave_verilog(),
        "        $display(\"COUNTS %0d %0d %0d\", reg_reads, reg_writes, ram_writes);\n",
    )
}

/// The test slave and the `fsmc_bridge` instance, for [`verilog_testbench`].
fn test_slave_verilog() -> String {
    let live_lo = *LIVE_WORDS.start();
    let live_hi = *LIVE_WORDS.end();
    format!(
        r#"    localparam [31:0] POISON = 32'h{RDATA_POISON:08x};
    wire [15:0] d_out;
    wire d_oe;
    wire [9:0] reg_addr;
    wire [31:0] reg_wdata;
    wire reg_we;
    wire reg_re;
    reg [31:0] reg_rdata = 32'h0;
    wire [9:0] ram_addr;
    wire [15:0] ram_wdata;
    wire ram_we;
    reg [15:0] ram_rdata = 16'h0;

    fsmc_bridge dut (
        .clock(clock), .reset(reset), .ne_n(ne_n), .noe_n(noe_n), .nwe_n(nwe_n),
        .a(a), .d_in(d_in), .d_out(d_out), .d_oe(d_oe), .reg_addr(reg_addr),
        .reg_wdata(reg_wdata), .reg_we(reg_we), .reg_re(reg_re), .reg_rdata(reg_rdata),
        .ram_addr(ram_addr), .ram_wdata(ram_wdata), .ram_we(ram_we), .ram_rdata(ram_rdata)
    );

    // 50 MHz: rising edges at 10 ns + k * 20 ns.
    always #10 clock = ~clock;

    // Test slave: register file (two-edge read, live registers
    // {live_lo:#x}..{live_hi:#x} = {{k, k}} at edge k), RAM (DSP-port contract).
    // Each array is written by this one process.
    reg [31:0] regs [0:1023];
    reg [15:0] ram [0:1023];
    reg [31:0] k = 32'h0;
    reg read_pending = 1'b0;
    reg [9:0] read_word = 10'h0;
    // The arrays start undefined: cleared one word a clock before the
    // first op (which starts a whole number of clocks later, so every phase
    // is the same as in the Rust run).
    reg clear = 1'b1;
    reg [9:0] clear_word = 10'h0;
    reg [31:0] reg_reads = 32'h0;
    reg [31:0] reg_writes = 32'h0;
    reg [31:0] ram_writes = 32'h0;
    always @(posedge clock) begin
        if (clear) begin
            regs[clear_word] <= 32'h0;
            ram[clear_word] <= 16'h0;
            clear_word <= clear_word + 10'd1;
            if (clear_word == 10'h3ff) clear <= 1'b0;
        end else begin
            if (read_pending)
                reg_rdata <= read_word[9:4] == 6'h3f
                    ? {{k[15:0], k[15:0]}} : regs[read_word];
            else if (reg_re)
                reg_rdata <= POISON;
            read_pending <= reg_re;
            if (reg_re) begin
                read_word <= reg_addr;
                reg_reads <= reg_reads + 1;
            end
            if (reg_we) begin
                reg_writes <= reg_writes + 1;
                if (reg_addr[9:4] != 6'h3f)
                    regs[reg_addr] <= reg_wdata;
            end
            ram_rdata <= ram[ram_addr];
            if (ram_we) begin
                ram_writes <= ram_writes + 1;
                ram[ram_addr] <= ram_wdata;
            end
        end
        k <= k + 1;
    end

"#
    )
}

/// The STM32F4 FSMC bus-functional model as a Verilog testbench module
/// `tb_module`: `dut` declares the FSMC-side nets (`d_out`, `d_oe`) and
/// instantiates the design (the testbench drives `clock`, `reset`, `ne_n`,
/// `noe_n`, `nwe_n`, `a`, `d_in`); the BFM reads the ops from `ops.hex`,
/// prints one `RD` line per read, then `final_display`, then `DONE`. Same
/// waveform and time grid as [`timeline`].
pub fn fsmc_bfm_verilog(
    timing: &FsmcTiming,
    ops: usize,
    tb_module: &str,
    dut_name: &str,
    dut: &str,
    final_display: &str,
) -> String {
    let FsmcTiming {
        addset,
        datast,
        busturn,
    } = *timing;
    let lead = read_lead_ticks();
    let header = format!(
        r#"// STM32F4 FSMC (mode 1) bus-functional model for {dut_name} (motionhdl).
`timescale 1ns / 1ps
`default_nettype none
module {tb_module};
    // Time in ticks of 1/{TICKS_PER_NS} ns: HCLK (168 MHz) = {HCLK_TICKS}, FPGA clock = {CLOCK_TICKS}.
    localparam [63:0] TICKS_PER_NS = 64'd{TICKS_PER_NS};
    localparam [63:0] HCLK = 64'd{HCLK_TICKS};
    localparam [63:0] CLOCK_TICKS = 64'd{CLOCK_TICKS};
    localparam [63:0] FIRST_EDGE = 64'd{FIRST_EDGE_TICKS};
    localparam [63:0] GRID = 64'd{GRID};
    localparam [63:0] CLEAR_CLOCKS = 64'd1100;
    localparam [63:0] ADDSET = 64'd{addset};
    localparam [63:0] DATAST = 64'd{datast};
    localparam [63:0] BUSTURN = 64'd{busturn};
    localparam [63:0] LEAD = 64'd{lead};
    localparam [63:0] END_OBS = 64'd{END_OBSERVATION_TICKS};
    localparam [63:0] DATA_DELAY = 64'd{WRITE_DATA_DELAY_TICKS};
    localparam [15:0] FLOATING_BUS = 16'h{FLOATING_BUS:04x};

    reg clock = 1'b0;
    reg reset = 1'b0;
    reg ne_n = 1'b1;
    reg noe_n = 1'b1;
    reg nwe_n = 1'b1;
    reg [11:0] a = 12'h0;
    reg [15:0] d_in = FLOATING_BUS;
"#
    );
    let bfm = format!(
        r#"    // The MCU's time, in ticks.
    reg [63:0] t = GRID + CLEAR_CLOCKS * CLOCK_TICKS;
    reg [63:0] fall;
    reg [63:0] rise;
    task automatic wait_until(input [63:0] when);
        begin
            #((when * 1.0) / TICKS_PER_NS - $realtime);
        end
    endtask
    function automatic [63:0] next_rising(input [63:0] now);
        begin
            if (now < FIRST_EDGE) next_rising = FIRST_EDGE;
            else next_rising = FIRST_EDGE + ((now - FIRST_EDGE) / CLOCK_TICKS + 64'd1) * CLOCK_TICKS;
        end
    endfunction
    function automatic [63:0] next_falling(input [63:0] now);
        begin
            next_falling = (now / CLOCK_TICKS + 64'd1) * CLOCK_TICKS;
        end
    endfunction

    reg oe_setup;
    reg [15:0] data_setup;
    // One access (mode 1): address phase, strobe, a write's hold.
    task automatic access(input ours, input write, input [11:0] addr, input [15:0] data);
        begin
            wait_until(t);
            ne_n = !ours;
            a = addr;
            if (write) d_in = ~data;
            fall = t + ADDSET * HCLK;
            rise = fall + DATAST * HCLK;
            wait_until(fall);
            if (write) begin
                nwe_n = 1'b0;
                wait_until(fall + DATA_DELAY);
                d_in = data;
                wait_until(rise);
                nwe_n = 1'b1;
                t = rise + HCLK;
            end else begin
                noe_n = 1'b0;
                wait_until(rise - LEAD);
                oe_setup = d_oe;
                data_setup = d_out;
                wait_until(rise - END_OBS);
                $display("RD %b %b %h %h", oe_setup, d_oe, data_setup, d_out);
                wait_until(rise);
                noe_n = 1'b1;
                t = rise;
            end
        end
    endtask
    task automatic finish_transaction;
        begin
            wait_until(t);
            ne_n = 1'b1;
            d_in = FLOATING_BUS;
            t = t + (1 + BUSTURN) * HCLK;
        end
    endtask

    reg [63:0] ops [0:{depth}];
    reg [63:0] op;
    integer i;
    // op: [63:60] kind, [59:48] A, [47:16] data, [15:0] parameter.
    initial begin
        $readmemh("ops.hex", ops);
        for (i = 0; ops[i][63:60] != 4'd0; i = i + 1) begin
            op = ops[i];
            case (op[63:60])
                4'd1: begin access(1'b1, 1'b0, op[59:48], 16'h0); finish_transaction; end
                4'd2: begin access(1'b1, 1'b1, op[59:48], op[31:16]); finish_transaction; end
                4'd3: begin
                    access(1'b1, 1'b0, op[59:48], 16'h0);
                    access(1'b1, 1'b0, op[59:48] + 12'd1, 16'h0);
                    finish_transaction;
                end
                4'd4: begin
                    access(1'b1, 1'b1, op[59:48], op[31:16]);
                    access(1'b1, 1'b1, op[59:48] + 12'd1, op[47:32]);
                    finish_transaction;
                end
                4'd5: begin access(1'b0, 1'b0, op[59:48], 16'h0); finish_transaction; end
                4'd6: begin access(1'b0, 1'b1, op[59:48], op[31:16]); finish_transaction; end
                4'd7: t = t + {{48'd0, op[15:0]}} * HCLK;
                4'd8: t = next_rising(t) + GRID + 64'd10 * {{48'd0, op[15:0]}};
                4'd9: begin
                    t = next_falling(t + 64'd4 * CLOCK_TICKS);
                    wait_until(t);
                    reset = 1'b1;
                    t = t + 64'd5 * CLOCK_TICKS;
                    wait_until(t);
                    reset = 1'b0;
                    t = t + GRID;
                end
                default: begin
                    $display("bad op %h", op);
                    $finish;
                end
            endcase
        end
        wait_until(t + 64'd8 * CLOCK_TICKS);
{final_display}        $display("DONE");
        $finish;
    end
endmodule
`default_nettype wire
"#,
        depth = ops,
    );
    header + dut + &bfm
}

/// Runs `ops` with `timing` through the generated `fsmc_bridge.v` under the
/// Verilog FSMC BFM: the observations and the slave's counts.
pub fn run_verilog(
    target: impl Into<Target>,
    ops: &[Op],
    timing: &FsmcTiming,
) -> Result<(Vec<Observation>, Counts), String> {
    let t = target.into();
    t.available()?;
    let text = t.text(&catalog::fsmc_bridge())?;
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = dir.path();
    let mut hex = String::new();
    for op in ops {
        let _ = writeln!(hex, "{:016x}", encode(op));
    }
    let _ = writeln!(hex, "{:016x}", 0);
    fs::write(d.join("tb.v"), verilog_testbench(timing, ops.len())).map_err(|e| e.to_string())?;
    fs::write(d.join("fsmc_bridge.v"), text).map_err(|e| e.to_string())?;
    fs::write(d.join("ops.hex"), hex).map_err(|e| e.to_string())?;
    let (stdout, _) = build_and_run(t.sim, d, "fsmc_bfm_tb", &["tb.v", "fsmc_bridge.v"], true)?;
    if !stdout.lines().any(|l| l == "DONE") {
        return Err(format!("testbench did not finish:\n{stdout}"));
    }
    let obs = parse_reads(&stdout)?;
    let mut counts = None;
    for l in stdout.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.first() == Some(&"COUNTS") && w.len() == 4 {
            let n = |s: &str| s.parse::<u64>().map_err(|_| format!("bad line `{l}`"));
            counts = Some(Counts {
                reg_reads: n(w[1])?,
                reg_writes: n(w[2])?,
                ram_writes: n(w[3])?,
            });
        }
    }
    Ok((obs, counts.ok_or("no COUNTS line")?))
}

/// The `RD` lines the Verilog BFM printed, one per read access.
pub fn parse_reads(stdout: &str) -> Result<Vec<Observation>, String> {
    let mut obs = Vec::new();
    for l in stdout.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.first() != Some(&"RD") {
            continue;
        }
        let bad = || format!("bad line `{l}`");
        if w.len() != 5 {
            return Err(bad());
        }
        let bit = |s: &str| match s {
            "1" => Ok(true),
            "0" => Ok(false),
            _ => Err(bad()),
        };
        let hex16 = |s: &str| u16::from_str_radix(s, 16).map_err(|_| bad());
        obs.push(Observation {
            oe_setup: bit(w[1])?,
            oe_end: bit(w[2])?,
            data_setup: hex16(w[3])?,
            data_end: hex16(w[4])?,
        });
    }
    Ok(obs)
}

/// Runs `ops` in the generated Verilog against the transaction model.
pub fn check_verilog(
    target: impl Into<Target>,
    name: &str,
    ops: &[Op],
    timing: &FsmcTiming,
) -> CheckReport {
    let t = target.into();
    let (want, _) = expected(ops);
    let mut r = CheckReport::new(
        "fsmc_bridge",
        &format!(
            "{name}: {} under the Verilog FSMC BFM vs transaction model",
            t.describe()
        ),
        want.len() as u64 + 1,
    );
    match run_verilog(t, ops, timing) {
        Ok((got, counts)) => compare(&mut r, &got, counts, ops),
        Err(e) if t.available().is_err() => return r.skip(e),
        Err(e) => r.failures.push(e),
    }
    r
}

/// The phase sweep in the generated Verilog with the documented timing.
pub fn sweep_verilog(target: impl Into<Target>) -> CheckReport {
    let (ops, cases) = phase_sweep_ops();
    assert_eq!(cases, SWEEP_CASES);
    check_verilog(target, "phase sweep", &ops, &documented_timing())
}

/// The long random run in the generated Verilog.
pub fn random_verilog(target: impl Into<Target>) -> CheckReport {
    let ops = random_ops(LONG_RANDOM.0, LONG_RANDOM.1);
    check_verilog(target, "random traffic", &ops, &documented_timing())
}

/// The long random run in rust-hdl.
pub fn random_rust() -> CheckReport {
    let ops = random_ops(LONG_RANDOM.0, LONG_RANDOM.1);
    check_rust("random traffic", &ops, &documented_timing()).0
}

/// The checks `motionhdl verify` shows for the bridge: the phase sweep and
/// the long random run in rust-hdl, and with `external` in Icarus and
/// Verilator.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![sweep_rust(&documented_timing()).0, random_rust()];
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            v.push(sweep_verilog(sim));
            v.push(random_verilog(sim));
        }
    }
    v
}
