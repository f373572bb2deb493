//! The safety and I/O block (docs/safety_io.md): against its model every
//! clock in rust-hdl, Icarus, Verilator and the post-synthesis netlist,
//! and its contract over a long run, each property shown able to fail.

use motionhdl_testbench::checks::safety_io::contract::{contract, Breakage, PROPERTIES};
use motionhdl_testbench::checks::safety_io::{random_rust, random_verilog, run_rust, stimulus};
use motionhdl_testbench::harness::doc_table_rows;
use motionhdl_testbench::scale;
use motionhdl_testbench::verilog_sim::{Simulator, Target};

#[test]
fn block_against_model_in_rust_hdl() {
    random_rust(100_000, 0x5afe_0001).assert_passed();
}

#[test]
fn one_axis_stop_logic_every_reachable_state_and_input() {
    let r = motionhdl_testbench::checks::safety_io::tour::stops_exhaustive();
    eprintln!("{}: {} of {} pairs", r.check, r.covered, r.expected);
    r.assert_passed();
    assert_eq!(r.covered, r.expected, "every pair visited");
    assert!(r.expected > 10_000, "{} pairs", r.expected);
}

#[test]
fn one_axis_soft_limits_and_counter_events_every_reachable_state_and_input() {
    use motionhdl_testbench::checks::safety_io::cause_tour;
    // Soft limits: CTRL 4 x CAUSE 4 x MASK 2 states; counter events: the
    // inputs before 4 x CAUSE 4 x MASK 2; all reachable, x 52 inputs.
    for r in [
        cause_tour::soft_limits_exhaustive(),
        cause_tour::counter_events_exhaustive(),
    ] {
        eprintln!("{}: {} of {} pairs", r.check, r.covered, r.expected);
        r.assert_passed();
        assert_eq!(r.covered, r.expected, "every pair visited");
        assert_eq!(r.expected, 4 * 4 * 2 * 52);
    }
}

#[test]
fn generated_verilog_against_model() {
    scale::run_sized("safety_io_icarus_clocks", |n| {
        random_verilog(Simulator::Icarus, n as usize, 0x5afe_0002)
    });
    scale::run_sized("safety_io_verilator_clocks", |n| {
        random_verilog(Simulator::Verilator, n as usize, 0x5afe_0003)
    });
}

#[test]
fn netlist_against_model() {
    let (icarus, verilator) = (Simulator::Icarus, Simulator::Verilator);
    scale::run_sized("safety_io_netlist_icarus_clocks", |n| {
        random_verilog(Target::netlist(icarus), n as usize, 0x5afe_0004)
    });
    scale::run_sized("safety_io_netlist_verilator_clocks", |n| {
        random_verilog(Target::netlist(verilator), n as usize, 0x5afe_0005)
    });
}

/// Clocks of the contract run, and how often each property's antecedent
/// must hold in it (so none passes by never being tested).
const CONTRACT_CLOCKS: usize = 200_000;
const MIN_COVERED: [u64; 10] = [
    100_000, 10_000, 500, 200, 100, 1_000, 100_000, 1_000, 10_000, 100,
];

#[test]
fn contract_holds_with_every_antecedent_covered() {
    let trace = run_rust(&stimulus(CONTRACT_CLOCKS, 0x5afe_0006));
    for (report, min) in contract(&trace).iter().zip(MIN_COVERED) {
        eprintln!("{}: {} cases", report.check, report.covered);
        report.assert_passed();
        assert!(
            report.covered >= min,
            "{}: antecedent held {} times, want at least {min}",
            report.check,
            report.covered
        );
    }
}

#[test]
fn each_contract_property_can_fail() {
    let trace = run_rust(&stimulus(20_000, 0x5afe_0007));
    assert!(contract(&trace).iter().all(|r| r.passed()));
    for b in Breakage::ALL {
        let reports = contract(&b.apply(&trace));
        assert!(
            !reports[b.property()].passed(),
            "{b:?} was not caught by `{}`",
            PROPERTIES[b.property()]
        );
    }
}

/// The register table and the numbers in docs/safety_io.md are the map's
/// and the spec's: acceptance testbenches are written from that page.
#[test]
fn the_docs_state_the_map_and_the_latencies() {
    use motionhdl_model::machine_inputs::{FILTER_TICKS, LIMIT_LATENCY, SOFT_LIMIT_LATENCY};
    use motionhdl_model::regmap::{self, Access};
    use motionhdl_model::safety_io::{ESTOP_LATENCY, IRQ_LATENCY, WATCHDOG_KEY};
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/safety_io.md");
    let doc = std::fs::read_to_string(path).unwrap();
    let rows = doc_table_rows(&doc, "## Registers", "| offset");
    let map = regmap::safety_io(4);
    assert_eq!(rows.len(), map.registers.len(), "one row per register");
    for (row, r) in rows.iter().zip(&map.registers) {
        let access = match r.access {
            Access::ReadOnly => "read-only",
            Access::WriteOnly => "write-only",
            Access::ReadWrite => "read-write",
            Access::WriteOneToClear => "write 1 to clear",
        };
        assert_eq!(row[..3], [&r.offset.to_string(), r.name, access], "{row:?}");
        for f in &r.fields {
            let bits = if f.width == 1 {
                format!("{} [{}]", f.name, f.lsb)
            } else if f.name == "AXES" && r.name != "INFO" || f.width == 4 && f.lsb == 0 {
                format!("{} [N-1:0]", f.name)
            } else if f.width == 4 && r.name != "INFO" {
                format!("{} [N+{}:{}]", f.name, f.lsb - 1, f.lsb)
            } else {
                format!("{} [{}:{}]", f.name, f.lsb + f.width - 1, f.lsb)
            };
            assert!(
                row[3].contains(&bits),
                "{}: `{bits}` not in {row:?}",
                r.name
            );
        }
    }
    assert!(rows[1][3].contains(&format!("reset value {:#x}", map.register("STATUS").reset)));
    let flat = doc.split_whitespace().collect::<Vec<_>>().join(" ");
    for fact in [
        format!("0x{WATCHDOG_KEY:X}"),
        format!("`ESTOP_LATENCY` = {ESTOP_LATENCY} edges"),
        format!("`IRQ_LATENCY` = {IRQ_LATENCY}"),
        format!("`FILTER_TICKS` = {FILTER_TICKS} ticks"),
        format!("`LIMIT_LATENCY` = {LIMIT_LATENCY} edges"),
        format!("`SOFT_LIMIT_LATENCY` = {SOFT_LIMIT_LATENCY} edges"),
    ] {
        assert!(
            flat.contains(&fact),
            "docs/safety_io.md does not say {fact:?}"
        );
    }
}
