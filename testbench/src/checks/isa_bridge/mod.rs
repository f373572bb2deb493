//! Checks of the ISA bridge (docs/isa_bridge.md).
//!
//! One stimulus language, the ISA bus-functional model's [`Op`]
//! ([`crate::bfm::isa`]), drives everything. The same op list runs
//! * through the rust-hdl block and the cycle-accurate model together, in
//!   continuous time ([`run_rust`]: HDL vs model at every clock edge),
//! * through the generated Verilog (or its netlist) in Icarus and
//!   Verilator, the model's pin stream replayed by [`crate::player`]
//!   ([`run_verilog`]),
//!
//! and what the PC and the DSP observe is compared with the
//! transaction-level model ([`expected`]).

use crate::bfm::isa::{self, Observation, Op};
use crate::harness::CheckReport;
use crate::player::{Peripheral, Rig};
use crate::verilog_sim::{Simulator, Target};
use motionhdl_hdl::catalog;
use motionhdl_model::isa_bridge::{reg, status, IsaCard};
use motionhdl_model::regmap::ISA_RAM_WORDS;
use motionhdl_model::IsaRam;

mod collision;
mod in_top;
mod rust_run;
mod stimulus;

pub use collision::*;
pub use in_top::*;
pub use rust_run::*;
pub use stimulus::*;

/// What the transaction model of the `ram` build says each read returns.
pub fn expected(ram: IsaRam, base: u8, ops: &[Op]) -> Vec<Observation> {
    let mut card = match ram {
        IsaRam::Internal => IsaCard::new(base),
        IsaRam::External => IsaCard::with_external_ram(base),
    };
    let mut out = Vec::new();
    for op in ops {
        match *op {
            Op::IoWrite {
                port, aen, data, ..
            } => {
                card.io_write(port, aen, data);
            }
            Op::IoRead { port, aen, .. } => out.push(match card.io_read(port, aen) {
                Some(v) => Observation::Io {
                    oe_setup: true,
                    oe_end: true,
                    data_setup: v,
                    data_end: v,
                },
                None => Observation::Io {
                    oe_setup: false,
                    oe_end: false,
                    data_setup: 0,
                    data_end: 0,
                },
            }),
            Op::DspWrite { addr, data } => card.dsp_write(addr, data),
            Op::DspRead { addr } => out.push(Observation::Dsp {
                data: card.dsp_read(addr),
            }),
            Op::Align { .. } => {}
            Op::Reset => card.reset(),
        }
    }
    out
}

/// Reads compared as the PC sees them: data only matters when driven.
pub fn same(got: &Observation, want: &Observation) -> bool {
    match (got, want) {
        (
            Observation::Io {
                oe_setup,
                oe_end,
                data_setup,
                data_end,
            },
            Observation::Io {
                oe_setup: w_oe,
                data_end: w_data,
                ..
            },
        ) => {
            *oe_setup == *w_oe
                && *oe_end == *w_oe
                && (!w_oe || (*data_setup == *w_data && *data_end == *w_data))
        }
        (a, b) => a == b,
    }
}

/// The external build's RAM chip in Verilog, the twin of [`DualPortSram`],
/// placed beside the bridge by the player.
pub const SRAM_V: &str = include_str!("../../../verilog/isa_dual_port_sram.v");

fn sram() -> Peripheral {
    // The facts the two RAM models share that the Verilog spells itself.
    assert!(
        SRAM_V.contains(&format!("16'h{SRAM_INVALID:04x}")),
        "isa_dual_port_sram.v and SRAM_INVALID disagree"
    );
    Peripheral::new("isa_dual_port_sram", "isa_dual_port_sram.v", SRAM_V)
}

/// Runs `ops` through the generated `isa_bridge.v` (or its netlist),
/// replaying the ISA bus-functional model's pin stream; the external build
/// runs beside its RAM chip. The Verilog RAM starts undefined, so the DSP
/// port first writes 0 to every word (the transaction model starts at 0).
pub fn run_verilog(
    target: impl Into<Target>,
    ram: IsaRam,
    base: u8,
    ops: &[Op],
) -> Result<Vec<Observation>, String> {
    let t = target.into();
    t.available()?;
    let module = catalog::isa_bridge(ram);
    let mut rig = Rig::new(&module, t.text(&module)?, isa::CLOCK);
    if ram == IsaRam::External {
        rig.peripherals.push(sram());
    }
    rig.sampled = isa::SAMPLED.map(String::from).to_vec();
    let mut all: Vec<Op> = vec![Op::Reset];
    all.extend((0..ISA_RAM_WORDS as u16).map(|addr| Op::DspWrite { addr, data: 0 }));
    // Writing the PC's mailbox word rang the bell: answer it (the write
    // leaves every other register as reset left it).
    all.push(standard_write(reg::STATUS, status::BELL));
    all.extend_from_slice(ops);
    let (stream, points) = isa::stream(base, &all);
    isa::observations(&points, &rig.play(t.sim, &stream)?)
}

/// Compares observations with the transaction model, one case per read.
fn compare(r: &mut CheckReport, got: &[Observation], want: &[Observation], ops: &[Op]) {
    if got.len() != want.len() {
        r.case(Some(format!(
            "{} reads observed, {} expected",
            got.len(),
            want.len()
        )));
        return;
    }
    let reads: Vec<&Op> = ops
        .iter()
        .filter(|o| matches!(o, Op::IoRead { .. } | Op::DspRead { .. }))
        .collect();
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        if !same(g, w) {
            r.failures.push(format!(
                "read #{k} ({:?}): observed {g:?}, transaction model {w:?}",
                reads.get(k)
            ));
        }
    }
}

fn build_name(ram: IsaRam) -> &'static str {
    match ram {
        IsaRam::Internal => "isa_bridge (internal RAM)",
        IsaRam::External => "isa_bridge (external SRAM)",
    }
}

/// Runs `ops` in the rust-hdl block of the `ram` build against its cycle
/// model and the transaction model; `cases` is how many cases the ops make.
pub fn check_rust(ram: IsaRam, name: &str, ops: &[Op], cases: u64) -> (CheckReport, RustRun) {
    let run = run_rust(ram, TEST_BASE, ops, None);
    report_rust(build_name(ram), ram, name, ops, cases, run)
}

/// [`check_rust`] of the external build through the external-RAM top.
pub fn check_rust_in_external_top(name: &str, ops: &[Op], cases: u64) -> (CheckReport, RustRun) {
    let run = run_rust_in_external_top(TEST_BASE, ops);
    let build = "motion_controller (external SRAM), its ISA side";
    report_rust(build, IsaRam::External, name, ops, cases, run)
}

/// The report of a rust-hdl run of `ops`: its mismatches with the cycle
/// model, and its reads against the transaction model of `ram`.
fn report_rust(
    build: &str,
    ram: IsaRam,
    name: &str,
    ops: &[Op],
    cases: u64,
    run: RustRun,
) -> (CheckReport, RustRun) {
    let mut r = CheckReport::new(
        build,
        &format!("{name}: rust-hdl vs cycle model every clock, reads vs transaction model"),
        cases,
    );
    r.failures.extend(run.mismatches.iter().cloned());
    compare(
        &mut r,
        &run.observations,
        &expected(ram, TEST_BASE, ops),
        ops,
    );
    r.covered = cases;
    (r, run)
}

/// Runs `ops` in the generated Verilog against the transaction model.
pub fn check_verilog(
    target: impl Into<Target>,
    ram: IsaRam,
    name: &str,
    ops: &[Op],
    cases: u64,
) -> CheckReport {
    let t = target.into();
    let mut r = CheckReport::new(
        build_name(ram),
        &format!(
            "{name}: {} through the ISA BFM's pin stream vs transaction model",
            t.describe()
        ),
        cases,
    );
    match run_verilog(t, ram, TEST_BASE, ops) {
        Ok(got) => {
            compare(&mut r, &got, &expected(ram, TEST_BASE, ops), ops);
            r.covered = cases;
        }
        Err(e) if t.available().is_err() => return r.skip(e),
        Err(e) => r.failures.push(e),
    }
    r
}

const EXHAUSTIVE_NAME: &str =
    "register x read/write x AEN x match x phase x command length x AUTO_INC";

/// The exhaustive case set in the rust-hdl block.
pub fn exhaustive_rust(ram: IsaRam) -> CheckReport {
    let (ops, cases) = exhaustive_ops();
    assert_eq!(cases, EXHAUSTIVE_CASES);
    check_rust(ram, EXHAUSTIVE_NAME, &ops, cases).0
}

/// The exhaustive case set in the generated Verilog.
pub fn exhaustive_verilog(target: impl Into<Target>, ram: IsaRam) -> CheckReport {
    let (ops, cases) = exhaustive_ops();
    assert_eq!(cases, EXHAUSTIVE_CASES);
    check_verilog(target, ram, EXHAUSTIVE_NAME, &ops, cases)
}

/// Words moved and checked by [`block_transfers`]: 2 runs × 3 × 1024.
pub const BLOCK_TRANSFER_WORDS: u64 = 2 * 3 * ISA_RAM_WORDS as u64;

fn block_transfers(pattern: u16) -> Vec<Op> {
    let mut ops = block_transfer_ops(false, pattern);
    ops.extend(block_transfer_ops(true, pattern ^ 0x5555));
    ops
}

/// Block transfers, both ways, both counter styles; one case per word
/// moved and checked.
pub fn block_transfer_rust(ram: IsaRam) -> CheckReport {
    let ops = block_transfers(0x1111);
    check_rust(
        ram,
        "2 KB block transfers both ways",
        &ops,
        BLOCK_TRANSFER_WORDS,
    )
    .0
}

/// Block transfers in the generated Verilog.
pub fn block_transfer_verilog(target: impl Into<Target>, ram: IsaRam) -> CheckReport {
    let ops = block_transfers(0x3333);
    check_verilog(
        target,
        ram,
        "2 KB block transfers both ways",
        &ops,
        BLOCK_TRANSFER_WORDS,
    )
}

/// Random bus traffic ([`random_ops`]: every register, other cards'
/// ports, AEN high, DSP-side accesses and the mailbox bells) through the
/// external-RAM top's pins (the bridge inside it), against the external
/// build's models; one case per op. Short: the top steps about 30 times
/// slower than the bridge alone.
pub fn external_top_rust(seed: u64, n: usize) -> (CheckReport, RustRun) {
    let ops = random_ops(seed, n);
    check_rust_in_external_top("random bus traffic", &ops, ops.len() as u64)
}

/// Every ISA bridge check for both builds; external simulators only when
/// `external` is set.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = Vec::new();
    for ram in [IsaRam::Internal, IsaRam::External] {
        v.push(exhaustive_rust(ram));
        v.push(block_transfer_rust(ram));
        v.push(random_rust(ram));
    }
    v.push(collision_check(None));
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            for ram in [IsaRam::Internal, IsaRam::External] {
                v.push(exhaustive_verilog(sim, ram));
                v.push(block_transfer_verilog(sim, ram));
                v.push(random_verilog(sim, ram));
            }
            v.push(collision_check(Some(sim.into())));
        }
    }
    v
}

pub use crate::harness::Rng;

/// The long random run in the rust-hdl block; one case per op.
pub fn random_rust(ram: IsaRam) -> CheckReport {
    let ops = random_ops(LONG_RANDOM.0, LONG_RANDOM.1);
    check_rust(ram, "random bus traffic", &ops, ops.len() as u64).0
}

/// The long random run in the generated Verilog.
pub fn random_verilog(target: impl Into<Target>, ram: IsaRam) -> CheckReport {
    let ops = random_ops(LONG_RANDOM.0, LONG_RANDOM.1);
    check_verilog(target, ram, "random bus traffic", &ops, ops.len() as u64)
}
