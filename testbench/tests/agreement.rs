//! Agreement of every implementation of every block on the same stimulus:
//! the bit-accurate model, the rust-hdl simulation, the generated Verilog
//! in Icarus and in Verilator (default options), and the post-synthesis
//! yosys netlist of the generated Verilog in Icarus.
//!
//! The first four legs are each block's own tests (docs/flow.md has the
//! table): each Verilog run there is compared with the model on the
//! stimulus the rust-hdl run is compared with, so all agree clock for
//! clock. Two rust-hdl runs used other stimulus than their Verilog runs
//! (the counter bank's seed, the ISA block transfers' data); this file
//! runs rust-hdl on the Verilog runs' stimulus too.
//!
//! And it adds the fifth leg: each block's existing Verilog check,
//! unchanged (same vectors, same expected results, same case counts), run
//! on the netlist (`motionhdl_testbench::netlist::SCRIPT`) instead of the
//! generated file. The counts below are the generated-file runs' counts;
//! the only shorter run is the counter bank's (30 000 clocks, as its
//! Icarus run, instead of Verilator's 10^7).
//!
//! Under CI a missing yosys or Icarus fails these tests.

use motionhdl_model::{Config, IsaRam};
use motionhdl_testbench::checks::{
    counter_bank, fsmc_bridge, isa_bridge, ls153, ls688, motion_controller, pulse_generator,
    pulse_mode_selector, quadrature_core,
};
use motionhdl_testbench::harness::{require_tool, require_tools};
use motionhdl_testbench::verilog_sim::{Simulator, Source, Target};
use motionhdl_testbench::{netlist, registry, scale, CheckReport};

fn tools() -> bool {
    require_tools(&["yosys", "iverilog", "vvp"]).is_some()
}

fn net() -> Target {
    Target::netlist(Simulator::Icarus)
}

/// Passed, on the netlist, with exactly `cases` cases.
fn passed(r: &CheckReport, cases: u64) {
    assert!(
        r.check.contains("netlist"),
        "{}: not a netlist run",
        r.check
    );
    r.assert_passed();
    assert_eq!(r.expected, cases, "{} / {}", r.block, r.check);
    assert_eq!(r.covered, cases, "{} / {}", r.block, r.check);
}

#[test]
fn ls153_netlist_every_input() {
    if tools() {
        passed(&ls153::ls153_verilog(net()), 4096);
    }
}

#[test]
fn pulse_mode_selectors_netlist_every_input_and_state() {
    if tools() {
        passed(&pulse_mode_selector::selector_verilog(net()), 8);
        // 4 output states × 16 inputs (reset, K, S2, S1), 130 clocks.
        passed(&pulse_mode_selector::registered_verilog(net()), 64);
    }
}

#[test]
fn ls688_netlist_every_input() {
    if tools() {
        passed(&ls688::ls688_verilog(net()), 1 << 17);
    }
}

#[test]
fn counter_bank_netlist_random_stimulus() {
    if tools() {
        // 4 axes × 28 bits, the Icarus run's seed and length: every clock's
        // read data in the checksum.
        assert_eq!(registry::COUNTER_BANK_CLOCKS, 30_000);
        let r = counter_bank::verilog_long_run(net(), registry::COUNTER_BANK_CLOCKS);
        passed(&r, 30_000);
    }
}

#[test]
fn counter_bank_rust_hdl_on_the_verilog_runs_stimulus() {
    // The rust-hdl bank's own long run (tests/counter.rs) uses another
    // seed; here it gets the Verilog runs' stimulus, every register of
    // every channel compared with the model every clock.
    let r = counter_bank::long_stimulus_hdl_seeded(30_000, counter_bank::VERILOG_SEED);
    r.assert_passed();
    assert_eq!(r.covered, 30_000);
}

#[test]
fn pulse_generator_netlist_random_clocks() {
    // The same stimulus (seed) as the Icarus run of the generated file.
    if tools() {
        let r = pulse_generator::random_verilog(net(), 100_000, 0x5eed_0002);
        passed(&r, 100_000);
    }
}

#[test]
fn quadrature_core_netlist_random_clocks() {
    if tools() {
        assert_eq!(registry::QUADRATURE_CLOCKS, 100_000);
        for (w, seed) in registry::QUADRATURE_RUNS {
            let r = quadrature_core::verilog_against_channel(
                net(),
                w,
                registry::QUADRATURE_CLOCKS,
                seed,
            );
            passed(&r, 100_000);
        }
    }
}

/// One RAM build's ISA bridge netlist; each build is its own test, so the
/// two run side by side.
fn isa_bridge_netlist(ram: IsaRam) {
    if tools() {
        passed(
            &isa_bridge::exhaustive_verilog(net(), ram),
            isa_bridge::EXHAUSTIVE_CASES,
        );
        assert_eq!(isa_bridge::EXHAUSTIVE_CASES, 6400);
        passed(
            &isa_bridge::block_transfer_verilog(net(), ram),
            isa_bridge::BLOCK_TRANSFER_WORDS,
        );
        assert_eq!(isa_bridge::BLOCK_TRANSFER_WORDS, 6144);
        // One case per op of the long random run: 5989 ops.
        let (seed, n) = isa_bridge::LONG_RANDOM;
        let ops = isa_bridge::random_ops(seed, n).len() as u64;
        assert_eq!(ops, 5989);
        passed(&isa_bridge::random_verilog(net(), ram), ops);
    }
}

#[test]
fn isa_bridge_netlist_internal_ram() {
    isa_bridge_netlist(IsaRam::Internal);
}

#[test]
fn isa_bridge_netlist_external_ram_and_collisions() {
    isa_bridge_netlist(IsaRam::External);
    if tools() {
        passed(&isa_bridge::collision_check(Some(net())), 172);
    }
}

#[test]
fn isa_bridge_rust_hdl_on_the_verilog_runs_block_transfers() {
    // The rust-hdl block-transfer check (tests/isa_bridge.rs) moves other
    // data; here it moves the Verilog runs' patterns.
    for ram in [IsaRam::Internal, IsaRam::External] {
        let mut ops = isa_bridge::block_transfer_ops(false, 0x3333);
        ops.extend(isa_bridge::block_transfer_ops(true, 0x3333 ^ 0x5555));
        let cases = isa_bridge::BLOCK_TRANSFER_WORDS;
        let (r, _) = isa_bridge::check_rust(ram, "Verilog runs' block transfers", &ops, cases);
        r.assert_passed();
        assert_eq!(r.covered, 6144);
    }
}

#[test]
fn fsmc_bridge_netlist_sweep_and_random() {
    if tools() {
        passed(&fsmc_bridge::sweep_verilog(net()), 2269);
        passed(&fsmc_bridge::random_verilog(net()), 1135);
    }
}

/// One RAM build's top-level netlist, with the reads its check makes; each
/// build is its own test, so the two run side by side. At 1 axis: the
/// plan reads every register and RAM word whatever the axes (the same
/// counts), an axis is one block's logic repeated, and the 4-axis gate
/// netlist in Icarus took about 250 s per build.
fn motion_controller_netlist(ram: IsaRam, reads: u64) {
    if tools() {
        let config = Config::default()
            .with_axes(1)
            .expect("1 axis")
            .with_isa_ram(ram);
        passed(&motion_controller::check_verilog(net(), &config), reads);
    }
}

#[test]
fn motion_controller_netlist_internal_ram() {
    motion_controller_netlist(IsaRam::Internal, 7232);
}

#[test]
fn motion_controller_netlist_external_ram() {
    motion_controller_netlist(IsaRam::External, 6150);
}

fn invert_y1(text: &str) -> String {
    netlist::invert_assign(text, "y1")
}

fn invert_rdata(text: &str) -> String {
    netlist::invert_assign(text, "rdata")
}

#[test]
fn an_inverted_netlist_output_fails_the_comparison() {
    if !tools() {
        return;
    }
    let mutated = |f| Target {
        sim: Simulator::Icarus,
        source: Source::MutatedNetlist(f),
    };
    // Combinational: the 74LS153 with Y1 inverted in its netlist. Every
    // vector then differs from the model (Y1 is compared on every input).
    let r = ls153::ls153_verilog(mutated(invert_y1));
    assert_eq!(r.covered, 4096);
    assert!(!r.passed(), "{}", r.result());
    assert_eq!(r.failures.len(), 21, "20 shown and the overflow line");
    assert!(r.failures[0].contains("model"), "{}", r.failures[0]);
    // Sequential: the counter bank's read data inverted; the checksum run
    // must fail.
    let r = counter_bank::verilog_long_run(mutated(invert_rdata), 2_000);
    assert!(!r.passed(), "{}", r.result());
    assert!(
        r.failures.iter().any(|f| f.contains("checksum")),
        "{:?}",
        r.failures
    );
    // The unmutated netlist passes the same short run.
    passed(&counter_bank::verilog_long_run(net(), 2_000), 2_000);
}

#[test]
fn every_build_has_a_plain_gate_level_netlist() {
    if require_tool("yosys").is_none() {
        return;
    }
    // Each build at the scale's axis count (knob `netlist_build_axes`; the
    // default build's 4 at the long scale): the netlist script's work is
    // per module, and an axis is the same logic again.
    let base = Config::default()
        .with_axes(scale::cases("netlist_build_axes"))
        .expect("netlist_build_axes is 1..=16");
    let mut modules = motionhdl_hdl::catalog::all(&base);
    let external = base.with_isa_ram(IsaRam::External);
    modules.push(motionhdl_hdl::catalog::isa_bridge(IsaRam::External));
    modules.push(motionhdl_hdl::catalog::motion_controller(&external));
    for m in &modules {
        let n = netlist::netlist(m).unwrap_or_else(|e| panic!("{}: {e}", m.name));
        // Gates only: no word-level operators survive techmap.
        let code: String = n.lines().filter(|l| !l.contains("//")).collect();
        // (`s ? b : a` is a 2:1 multiplexer gate and may appear.)
        for op in [" + ", " - ", " * ", " == ", " < ", " > ", " << ", " >> "] {
            assert!(!code.contains(op), "{}: `{op}` in the netlist", m.name);
        }
        let (gates, flops) = netlist::size(&n);
        assert!(gates > 0, "{}: no gates", m.name);
        eprintln!("{}: {gates} assignments, {flops} always blocks", m.name);
        // Cached: the same text comes back without running yosys again.
        assert_eq!(netlist::netlist(m).unwrap(), n);
    }
}
