//! The suite's two scales: one set of checks, run at the default scale by
//! `bash scripts/test` and `motionhdl verify`, and at the long scale by
//! `bash scripts/test --long` and `motionhdl verify --long`
//! (`MOTIONHDL_LONG=1`). Only the long random runs and the wide instances
//! change with the scale; every exhaustive tour, agreement leg, proof,
//! export and block-level contract breakage runs at both (the breakages of
//! a block's proof inside the whole top are a wide instance: a spread of
//! them at the default scale, all at the long one).
//!
//! Each [`Knob`] is one check's case count at both scales and the floor
//! below which its default may not drop (`tests/scale.rs` holds the table
//! to its floors and docs/testing.md to the table).

/// The environment variable that selects the long scale.
pub const LONG_VAR: &str = "MOTIONHDL_LONG";

/// One check's size at both scales.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Knob {
    /// The name the check asks for.
    pub name: &'static str,
    /// The check it sizes (its test, as `binary::test`).
    pub check: &'static str,
    /// What a case is.
    pub unit: &'static str,
    pub default: u64,
    pub long: u64,
    /// The least the default may be: a later cut below it fails the suite.
    pub floor: u64,
}

/// Every knob, one row per check.
pub const KNOBS: &[Knob] = &[
    Knob {
        name: "counter_bank_verilator_clocks",
        check: "counter::generated_verilog_in_verilator_matches_model_for_the_long_run",
        unit: "clocks",
        default: 1_000_000,
        long: 10_000_000,
        floor: 1_000_000,
    },
    Knob {
        name: "synth_check_axes",
        check: "exports::synth*_has_no_latch_multiple_driver_or_undriven_net (3 flows)",
        unit: "axes of each build",
        default: 1,
        long: 4,
        floor: 1,
    },
    Knob {
        name: "netlist_build_axes",
        check: "agreement::every_build_has_a_plain_gate_level_netlist",
        unit: "axes of each build",
        default: 1,
        long: 4,
        floor: 1,
    },
    Knob {
        name: "ramped_move_cases",
        check: "pulse_generator::random_ramped_moves_end_exactly",
        unit: "proptest moves",
        default: 12,
        long: 48,
        floor: 12,
    },
    Knob {
        name: "safety_io_icarus_clocks",
        check: "safety_io::generated_verilog_against_model",
        unit: "clocks in Icarus",
        default: 30_000,
        long: 100_000,
        floor: 30_000,
    },
    Knob {
        name: "safety_io_verilator_clocks",
        check: "safety_io::generated_verilog_against_model",
        unit: "clocks in Verilator",
        default: 300_000,
        long: 1_000_000,
        floor: 300_000,
    },
    Knob {
        name: "safety_io_netlist_icarus_clocks",
        check: "safety_io::netlist_against_model",
        unit: "clocks in Icarus",
        default: 10_000,
        long: 20_000,
        floor: 10_000,
    },
    Knob {
        name: "safety_io_netlist_verilator_clocks",
        check: "safety_io::netlist_against_model",
        unit: "clocks in Verilator",
        default: 100_000,
        long: 200_000,
        floor: 100_000,
    },
    Knob {
        name: "formal_in_top_breaks",
        check: "formal::every_property_fails_on_its_broken_copy",
        unit: "breaks of each in-top proof",
        default: 3,
        long: 12,
        floor: 3,
    },
    Knob {
        name: "servo_dac_netlist_icarus_clocks",
        check: "servo_dac::netlist_against_model",
        unit: "clocks in Icarus",
        default: 10_000,
        long: 20_000,
        floor: 10_000,
    },
    Knob {
        name: "servo_dac_netlist_verilator_clocks",
        check: "servo_dac::netlist_against_model",
        unit: "clocks in Verilator",
        default: 50_000,
        long: 100_000,
        floor: 50_000,
    },
    Knob {
        name: "external_ram_walk_axes",
        check: "motion_controller::external_ram_build_registers_and_no_ram_window",
        unit: "axes of the build",
        default: 1,
        long: 4,
        floor: 1,
    },
    Knob {
        name: "servo_card_walk_axes",
        check: "motion_controller::servo_card_build_registers_through_fsmc",
        unit: "axes of the build",
        default: 1,
        long: 2,
        floor: 1,
    },
    Knob {
        name: "netlist_checksum_axes",
        check: "top_model::the_post_synthesis_netlist_reaches_the_models_checksums",
        unit: "axes of the top",
        default: 1,
        long: 4,
        floor: 1,
    },
];

/// True at the long scale: `MOTIONHDL_LONG` set, and not to `0`.
pub fn long() -> bool {
    std::env::var_os(LONG_VAR).is_some_and(|v| !v.is_empty() && v != "0")
}

/// The knob called `name`; panics naming it when there is none (a check
/// asking for a size the table does not state).
pub fn knob(name: &str) -> &'static Knob {
    KNOBS
        .iter()
        .find(|k| k.name == name)
        .unwrap_or_else(|| panic!("scale: no knob `{name}` in scale::KNOBS"))
}

/// `name`'s case count at this run's scale.
pub fn cases(name: &str) -> u64 {
    at(name, long())
}

/// `name`'s case count at the given scale.
pub fn at(name: &str, long: bool) -> u64 {
    let k = knob(name);
    if long {
        k.long
    } else {
        k.default
    }
}

/// The scale's name, for reports.
pub fn name() -> &'static str {
    if long() {
        "long"
    } else {
        "default"
    }
}

/// Runs `check` at knob `name`'s size for this run's scale and asserts
/// that it passed and covered exactly that many cases.
pub fn run_sized(name: &str, check: impl FnOnce(u64) -> crate::CheckReport) {
    let cases = cases(name);
    let r = check(cases);
    r.assert_passed();
    assert_eq!(r.covered, cases, "{name}: {}", r.check);
}
