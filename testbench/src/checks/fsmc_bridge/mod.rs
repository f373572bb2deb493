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

use crate::bfm::fsmc::{self, documented_timing, Observation, Op, CLOCK_TICKS, PHASES};
use crate::harness::CheckReport;
use crate::player::{Rig, Row};
use crate::verilog_sim::{Simulator, Target};
use motionhdl_hdl::catalog;
use motionhdl_model::fsmc_bridge::{
    self as m, FsmcSlave, FsmcTiming, FsmcTransactions, PlainSlave,
};

mod rust_run;
mod slave;
mod stimulus;

pub use rust_run::*;
pub use slave::*;
pub use stimulus::*;

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
