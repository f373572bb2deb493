//! FSMC bridge: the documented FSMC timing at every phase of HCLK against
//! the FPGA clock, its minimality, random traffic (proptest and a long
//! fixed run), in rust-hdl and in the generated Verilog (Icarus, Verilator),
//! and the export's lint.

use motionhdl_model::fsmc_bridge::{self as m, FsmcTiming};
use motionhdl_testbench::bfm::fsmc::{self as bus, Op};
use motionhdl_testbench::checks::fsmc_bridge as fsmc;
use motionhdl_testbench::harness::require_tool;
use motionhdl_testbench::verilog_sim::Simulator;
use std::process::Command;

#[test]
fn the_documented_timing_is_addset_4_datast_21_busturn_0() {
    let t = bus::documented_timing();
    assert_eq!(
        t,
        FsmcTiming {
            addset: 4,
            datast: 21,
            busturn: 0
        }
    );
    assert_eq!(t.btr(), 0x0000_1504);
    // The sweep's grid: 84 distinct phases of HCLK against the FPGA clock.
    assert_eq!(bus::PHASES, 84);
    assert_eq!(fsmc::SWEEP_CASES, 84 * 12);
    // Both clocks are whole on the 1/42 ns grid.
    let tick_hz = bus::TICKS_PER_NS * 1_000_000_000;
    assert_eq!(bus::HCLK_TICKS * bus::HCLK_HZ, tick_hz);
    assert_eq!(bus::CLOCK_TICKS * bus::FPGA_CLOCK_HZ, tick_hz);
}

#[test]
fn phase_sweep_rust_hdl() {
    let (r, cases) = fsmc::sweep_rust(&bus::documented_timing());
    assert_eq!(cases, 1008);
    // One case per read (27 a phase) plus the transaction counts.
    assert_eq!(r.expected, 2269);
    r.assert_passed();
}

#[test]
fn one_hclk_less_of_datast_or_addset_fails() {
    let t = bus::documented_timing();
    let short_data = FsmcTiming {
        datast: t.datast - 1,
        ..t
    };
    let bad = fsmc::failing_phases(&short_data);
    assert!(
        !bad.is_empty(),
        "DATAST {} passes every phase: the documented value is not the minimum",
        short_data.datast
    );
    eprintln!(
        "DATAST {}: {} of {} phases fail: {bad:?}",
        short_data.datast,
        bad.len(),
        bus::PHASES
    );
    let short_addr = FsmcTiming {
        addset: t.addset - 1,
        ..t
    };
    let bad = fsmc::failing_phases(&short_addr);
    assert!(
        !bad.is_empty(),
        "ADDSET {} passes every phase",
        short_addr.addset
    );
    eprintln!(
        "ADDSET {}: {} of {} phases fail: {bad:?}",
        short_addr.addset,
        bad.len(),
        bus::PHASES
    );
    // And the documented timing passes every phase on its own.
    assert!(fsmc::failing_phases(&t).is_empty());
    // A lone register read (16 bits, register low half) at each phase: the
    // data is late at the phases where NOE# falls just after an edge.
    let late = fsmc::read_failing_phases(&short_data);
    eprintln!(
        "DATAST {}: a lone register read fails at {} of {} phases: {late:?}",
        short_data.datast,
        late.len(),
        bus::PHASES
    );
    assert!(!late.is_empty() && late.len() < bus::PHASES as usize);
    assert!(fsmc::read_failing_phases(&t).is_empty());
}

#[test]
fn phase_sweep_icarus() {
    let r = fsmc::sweep_verilog(Simulator::Icarus);
    assert_eq!(r.expected, 2269);
    r.assert_passed();
}

#[test]
fn phase_sweep_verilator() {
    let r = fsmc::sweep_verilog(Simulator::Verilator);
    assert_eq!(r.expected, 2269);
    r.assert_passed();
}

#[test]
fn random_traffic_all_simulators() {
    let r = fsmc::random_rust();
    assert!(r.expected > 1000, "{}", r.expected);
    r.assert_passed();
    fsmc::random_verilog(Simulator::Icarus).assert_passed();
    fsmc::random_verilog(Simulator::Verilator).assert_passed();
}

#[test]
fn a_torn_or_wrong_read_is_caught() {
    // The comparison must be able to fail: a live register read as two
    // 16-bit halves of different samples (a lone high half after another
    // word's low half) is not one sample, and a wrong value is not the
    // written one.
    let ops = [
        Op::Reset,
        Op::Write32 { a: 2, data: 7 },
        Op::Read32 { a: 2 },
        Op::Read16 { a: 0x7e0 },
        Op::Read16 { a: 0x7e3 },
    ];
    let run = fsmc::run_rust(&ops, &bus::documented_timing());
    assert!(run.mismatches.is_empty(), "{:?}", run.mismatches);
    let (want, _) = fsmc::expected(&ops);
    assert_eq!(want[0], fsmc::Expect::Data(7));
    assert_eq!(run.observations[0].data_end, 7);
    // Two live halves of different samples differ.
    assert_ne!(run.observations[2].data_end, run.observations[3].data_end);
    assert_eq!(want[3], fsmc::Expect::Live);
}

#[test]
fn export_lints_clean() {
    let m = motionhdl_hdl::catalog::fsmc_bridge();
    assert_eq!(m.name, "fsmc_bridge");
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("fsmc_bridge.v");
    std::fs::write(&f, &m.text).unwrap();
    if require_tool("verilator").is_some() {
        let o = Command::new("verilator")
            .args(["--lint-only", "-Wall"])
            .arg(&f)
            .output()
            .unwrap();
        assert!(
            o.status.success() && o.stderr.is_empty(),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    if require_tool("iverilog").is_some() {
        let o = Command::new("iverilog")
            .args(["-g2005", "-Wall", "-o"])
            .arg(dir.path().join("x"))
            .arg(&f)
            .output()
            .unwrap();
        assert!(
            o.status.success() && o.stderr.is_empty() && o.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn the_timing_follows_the_clocks() {
    // A faster FPGA clock needs fewer HCLKs; a slower one more.
    let t = |f| m::stm32f4_timing(f, 168_000_000);
    assert!(t(100_000_000).datast < t(50_000_000).datast);
    assert!(t(25_000_000).datast > t(50_000_000).datast);
    assert!(t(25_000_000).addset > t(50_000_000).addset);
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// Random 16/32-bit reads and writes of registers (live ones too)
        /// and RAM, other banks' cycles, idle times and phases: rust-hdl vs
        /// the cycle model every clock, every read and the transaction
        /// counts vs the transaction model.
        #[test]
        fn random_sequences(seed in any::<u64>(), n in 1usize..40) {
            let ops = fsmc::random_ops(seed, n);
            let (r, run) = fsmc::check_rust("proptest", &ops, &bus::documented_timing());
            prop_assert!(r.failures.is_empty(), "seed {seed:#x} n {n}: {:?}", r.failures);
            prop_assert_eq!(r.covered, r.expected);
            prop_assert!(run.clocks > 0);
        }
    }
}
