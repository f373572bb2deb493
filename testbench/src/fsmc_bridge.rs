//! Checks of the FSMC bridge (docs/fsmc_bridge.md).
//!
//! One stimulus language, the STM32F4 FSMC bus-functional model's [`Op`]
//! ([`crate::bfm::fsmc`]), drives everything. The same op list runs
//! * through the rust-hdl block and the cycle model together, with a test
//!   slave (register file with the two-edge read and live registers that
//!   change every clock; RAM with the DSP-port contract): [`run_rust`];
//! * through the generated Verilog (or its netlist) beside the same slave
//!   in Verilog (`testbench/verilog/fsmc_test_slave.v`), in Icarus and
//!   Verilator, the model's pin stream replayed by [`crate::player`]:
//!   [`run_verilog`];
//!
//! and every read, as the MCU samples it, is compared with the
//! transaction-level model ([`expected`]), as are the numbers of register
//! reads, register writes and RAM writes (nothing lost or doubled).

use crate::bfm::fsmc::{
    self, documented_timing, timeline, Event, Observation, Op, CLOCK_TICKS, FIRST_EDGE_TICKS,
    PHASES,
};
use crate::harness::{settle, CheckReport};
use crate::player::{Peripheral, Rig, Row};
use crate::verilog_sim::{Simulator, Target};
use motionhdl_hdl::{catalog, FsmcBridge};
use motionhdl_model::fsmc_bridge::{
    self as m, FsmcBridgeModel, FsmcOutputs, FsmcPins, FsmcSlave, FsmcTiming, FsmcTransactions,
    PlainSlave,
};
use rust_hdl::prelude::*;

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

/// The test slave in Verilog, the twin of [`TestSlave`], placed beside the
/// bridge by the player.
pub const TEST_SLAVE_V: &str = include_str!("../verilog/fsmc_test_slave.v");
/// Clocks the Verilog slave spends clearing its arrays; the bus stream
/// starts this many whole clocks late.
pub const SLAVE_CLEAR_CLOCKS: u64 = 1100;

fn test_slave() -> Peripheral {
    // The one fact the two slaves share that the Verilog spells itself.
    assert!(
        TEST_SLAVE_V.contains(&format!("32'h{RDATA_POISON:08x}")),
        "fsmc_test_slave.v and RDATA_POISON disagree"
    );
    Peripheral::new("fsmc_test_slave", "fsmc_test_slave.v", TEST_SLAVE_V)
}

/// Runs `ops` with `timing` through the generated `fsmc_bridge.v` (or its
/// netlist) and the test slave, replaying the FSMC bus-functional model's
/// pin stream: the observations and the slave's counts.
pub fn run_verilog(
    target: impl Into<Target>,
    ops: &[Op],
    timing: &FsmcTiming,
) -> Result<(Vec<Observation>, Counts), String> {
    let t = target.into();
    t.available()?;
    let module = catalog::fsmc_bridge();
    let mut rig = Rig::new(&module, t.text(&module)?, fsmc::CLOCK);
    rig.peripherals.push(test_slave());
    rig.sampled = ["d_oe", "d_out", "reg_reads", "reg_writes", "ram_writes"]
        .map(String::from)
        .to_vec();
    let mut stream = fsmc::stream(ops, timing).delayed(SLAVE_CLEAR_CLOCKS * CLOCK_TICKS);
    // The counts, once everything has settled.
    stream.rows.push(Row::Sample { at: stream.end });
    let samples = rig.play(t.sim, &stream)?;
    let (last, reads) = samples.split_last().ok_or("no samples")?;
    let counts = match last[2..] {
        [Some(reg_reads), Some(reg_writes), Some(ram_writes)] => Counts {
            reg_reads,
            reg_writes,
            ram_writes,
        },
        _ => return Err(format!("unreadable counts {last:?}")),
    };
    Ok((fsmc::observations(reads)?, counts))
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
            "{name}: {} through the FSMC BFM's pin stream vs transaction model",
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
