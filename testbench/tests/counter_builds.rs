//! Counter bank build options (docs/counter_bank.md, "Build options"):
//! every option in its "off" state through the exhaustive tours that apply
//! to it, random traffic against the model in rust-hdl, Icarus and
//! Verilator, and what each option visibly removes. The "on" state of every
//! option is the default build, which `counter.rs` checks.

use motionhdl_model::counter::{BusCycle, CounterFeatures, CounterParams};
use motionhdl_model::regmap;
use motionhdl_testbench::checks::counter_bank::{self, BankPair};
use motionhdl_testbench::checks::counter_channel::{self, ctrl_value};
use motionhdl_testbench::checks::input_filter;
use motionhdl_testbench::harness::require_tool;
use motionhdl_testbench::scenarios::counter_bank::quadrature;
use motionhdl_testbench::verilog_sim::Simulator;

const FULL: CounterFeatures = CounterFeatures::ALL;

/// Each option off alone, then the DSP seed card's set (only the snapshot),
/// then every option off.
fn partial_builds() -> [CounterFeatures; 6] {
    [
        CounterFeatures {
            filter: false,
            ..FULL
        },
        CounterFeatures {
            index: false,
            ..FULL
        },
        CounterFeatures {
            error: false,
            ..FULL
        },
        CounterFeatures {
            snapshot: false,
            ..FULL
        },
        CounterFeatures::from_bits(8),
        CounterFeatures::from_bits(0),
    ]
}

#[test]
fn input_filter_left_out_every_reachable_state_and_input_for_every_setting() {
    let r = input_filter::filter_exhaustive_built(false);
    // Without the count only s1, s2 and the level remain: 8 states × 4 inputs
    // for each of the 16 settings.
    assert_eq!(r.expected, 16 * 8 * 4, "pairs enumerated");
    r.assert_passed();
}

#[test]
fn channel_core_of_builds_without_index_error_or_filter_every_reachable_pair() {
    let reports = counter_channel::core_checks_of_partial_builds();
    assert_eq!(reports.len(), 3, "without index, without error, all three");
    for r in reports {
        assert!(
            r.expected > 500,
            "{}: enumerated only {} pairs",
            r.check,
            r.expected
        );
        r.assert_passed();
    }
}

#[test]
fn every_partial_build_rust_hdl_matches_model_every_clock() {
    for f in partial_builds() {
        let r = counter_bank::long_stimulus_hdl_built(10_000, 4242, f);
        assert_eq!(r.expected, 10_000);
        r.assert_passed();
    }
}

#[test]
fn every_partial_build_generated_verilog_in_icarus_matches_model() {
    if require_tool("iverilog").is_none() {
        return;
    }
    for f in partial_builds() {
        counter_bank::verilog_long_run_built(Simulator::Icarus, 20_000, f).assert_passed();
    }
}

#[test]
fn every_partial_build_generated_verilog_in_verilator_matches_model() {
    if require_tool("verilator").is_none() {
        return;
    }
    for f in partial_builds() {
        let r = counter_bank::verilog_long_run_built(Simulator::Verilator, 1_000_000, f);
        assert_eq!(r.expected, 1_000_000);
        r.assert_passed();
    }
}

/// A one-channel bank of `features` after reset, in X4 with `fields` of CTRL
/// written (absent ones included, so they are shown ignored).
fn bank(features: CounterFeatures, fields: &[(&str, u32)]) -> BankPair<1> {
    let params = CounterParams::new(28, regmap::ERR_COUNT_BITS).with_features(features);
    let mut p = BankPair::<1>::with_params(params);
    let idle = [(false, false, false)];
    p.reset(&idle, 4).unwrap();
    let ctrl = p.map.array("CH").address(0, "CTRL");
    p.write(&idle, ctrl, ctrl_value(28, fields)).unwrap();
    p
}

fn read(p: &mut BankPair<1>, pins: (bool, bool, bool), reg: &str) -> u32 {
    let addr = p.map.array("CH").address(0, reg);
    p.read(&[pins], addr).unwrap()
}

fn run(p: &mut BankPair<1>, pins: (bool, bool, bool), clocks: usize) {
    for _ in 0..clocks {
        p.step(&[pins], false, &BusCycle::default()).unwrap();
    }
}

#[test]
fn info_tells_firmware_which_features_the_build_has() {
    for f in CounterFeatures::every() {
        let mut p = bank(f, &[]);
        let info = p.map.register("INFO").offset;
        let v = p.read(&[(false, false, false)], info).unwrap();
        assert_eq!((v >> 24) & 15, f.bits(), "{f:?}: INFO = {v:#x}");
        let err_bits = (v >> 16) & 15;
        assert_eq!(err_bits != 0, f.error, "{f:?}: INFO.ERR_BITS = {err_bits}");
    }
}

#[test]
fn each_option_removes_what_it_names_and_nothing_else() {
    let fields = [
        ("MODE", regmap::mode::X4),
        ("ERR_EN", 1),
        ("IDX_LATCH", 1),
        ("FILTER_AB", 15),
    ];
    let ctrl_of = |f: CounterFeatures| {
        let mut p = bank(f, &fields);
        read(&mut p, (false, false, false), "CTRL")
    };
    let full_ctrl = ctrl_of(FULL);
    assert_eq!(full_ctrl, ctrl_value(28, &fields));
    for (f, gone) in [
        (partial_builds()[0], ctrl_value(28, &[("FILTER_AB", 15)])),
        (partial_builds()[1], ctrl_value(28, &[("IDX_LATCH", 1)])),
        (partial_builds()[2], ctrl_value(28, &[("ERR_EN", 1)])),
        (partial_builds()[3], 0),
    ] {
        assert_eq!(
            ctrl_of(f),
            full_ctrl & !gone,
            "{f:?}: CTRL keeps only its fields"
        );
    }

    // An illegal jump (A and B together) sets STATUS.ERR only with the
    // error option; a count then reads at once only without the snapshot.
    for f in [FULL, partial_builds()[2], partial_builds()[3]] {
        let mut p = bank(f, &[("MODE", regmap::mode::X4), ("ERR_EN", 1)]);
        run(&mut p, (true, true, false), 8);
        let status = read(&mut p, (true, true, false), "STATUS");
        let snapshot = if f.snapshot {
            assert_eq!(status, 0, "{f:?}: STATUS before any SNAPSHOT");
            let s = p.map.register("SNAPSHOT").offset;
            p.write(&[(true, true, false)], s, 0).unwrap();
            read(&mut p, (true, true, false), "STATUS")
        } else {
            status
        };
        let err = snapshot & 1 != 0;
        assert_eq!(err, f.error, "{f:?}: STATUS = {snapshot:#x}");
        for phase in 3..6 {
            let (a, b) = quadrature(phase);
            run(&mut p, (a, b, false), 6);
        }
        let (a, b) = quadrature(5);
        let count = read(&mut p, (a, b, false), "COUNT");
        assert_eq!(
            count != 0,
            !f.snapshot,
            "{f:?}: COUNT = {count} before SNAPSHOT"
        );
    }

    // A glitch of one clock on A: FILTER_AB = 15 rejects it; without the
    // filter option it passes (the setting is not stored).
    for f in [FULL, partial_builds()[0]] {
        let mut p = bank(f, &[("MODE", regmap::mode::PULSE_DIR), ("FILTER_AB", 15)]);
        run(&mut p, (true, false, false), 1);
        run(&mut p, (false, false, false), 30);
        let s = p.map.register("SNAPSHOT").offset;
        p.write(&[(false, false, false)], s, 0).unwrap();
        let count = read(&mut p, (false, false, false), "COUNT");
        assert_eq!(
            count == 1,
            !f.filter,
            "{f:?}: COUNT = {count} after a glitch"
        );
    }

    // An index pulse with IDX_LATCH after 3 steps: INDEX reads 3 with the
    // index option; without it the address reads 0.
    for f in [FULL, partial_builds()[1]] {
        let mut p = bank(f, &[("MODE", regmap::mode::X4), ("IDX_LATCH", 1)]);
        for phase in 1..4 {
            let (a, b) = quadrature(phase);
            run(&mut p, (a, b, false), 6);
        }
        let (a, b) = quadrature(3);
        run(&mut p, (a, b, true), 6);
        run(&mut p, (a, b, false), 6);
        let s = p.map.register("SNAPSHOT").offset;
        p.write(&[(a, b, false)], s, 0).unwrap();
        let addr = p.map.array("CH").address(0, "INDEX");
        let index = p.read(&[(a, b, false)], addr).unwrap();
        assert_eq!(index, if f.index { 3 } else { 0 }, "{f:?}");
    }
}
