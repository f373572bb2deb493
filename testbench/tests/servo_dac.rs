//! The servo DAC block (docs/servo_dac.md): against its model every clock
//! in rust-hdl, Icarus, Verilator and the post-synthesis netlist, its
//! contract on the DAC pins over a long run and its zero-jitter servo
//! loop, each property shown able to fail.

use motionhdl_testbench::checks::servo_dac::contract::{
    contract, servo_run, zero_jitter, Breakage, PROPERTIES,
};
use motionhdl_testbench::checks::servo_dac::{random_rust, random_verilog, run_rust, stimulus};
use motionhdl_testbench::harness::doc_table_rows;
use motionhdl_testbench::scale;
use motionhdl_testbench::verilog_sim::{Simulator, Target};

#[test]
fn block_against_model_in_rust_hdl() {
    random_rust(100_000, 0xdac0_0001).assert_passed();
}

#[test]
fn interface_control_every_reachable_state_and_input() {
    let r = motionhdl_testbench::checks::servo_dac::tour::control_exhaustive();
    eprintln!("{}: {} of {} pairs", r.check, r.covered, r.expected);
    r.assert_passed();
    assert_eq!(r.covered, r.expected, "every pair visited");
    assert!(r.expected > 10_000, "{} pairs", r.expected);
}

#[test]
fn serial_interface_control_every_reachable_state_and_input() {
    let r = motionhdl_testbench::checks::servo_dac::tour::serial_exhaustive();
    eprintln!("{}: {} of {} pairs", r.check, r.covered, r.expected);
    r.assert_passed();
    assert_eq!(r.covered, r.expected, "every pair visited");
    assert!(r.expected > 10_000, "{} pairs", r.expected);
}

#[test]
fn generated_verilog_against_model() {
    random_verilog(Simulator::Icarus, 50_000, 0xdac0_0002).assert_passed();
    random_verilog(Simulator::Verilator, 500_000, 0xdac0_0003).assert_passed();
}

#[test]
fn netlist_against_model() {
    let (icarus, verilator) = (Simulator::Icarus, Simulator::Verilator);
    scale::run_sized("servo_dac_netlist_icarus_clocks", |n| {
        random_verilog(Target::netlist(icarus), n as usize, 0xdac0_0004)
    });
    scale::run_sized("servo_dac_netlist_verilator_clocks", |n| {
        random_verilog(Target::netlist(verilator), n as usize, 0xdac0_0005)
    });
}

/// Clocks of the contract run, and how often each property's antecedent
/// must hold in it (so none passes by never being tested).
const CONTRACT_CLOCKS: usize = 100_000;
const MIN_COVERED: [u64; 4] = [100_000, 10_000, 5_000, 400];

#[test]
fn contract_holds_with_every_antecedent_covered() {
    let trace = run_rust(&stimulus(CONTRACT_CLOCKS, 0xdac0_0006));
    let reports = contract(&trace);
    assert_eq!(reports.len(), PROPERTIES.len());
    for (r, min) in reports.iter().zip(MIN_COVERED) {
        eprintln!("{}: {} cases", r.check, r.covered);
        r.assert_passed();
        assert!(r.covered >= min, "{}: only {} cases", r.check, r.covered);
    }
}

#[test]
fn a_servo_loop_updates_the_dac_a_fixed_time_after_every_tick() {
    for serial in [false, true] {
        let trace = servo_run(40, serial);
        let r = zero_jitter(&trace, serial);
        eprintln!("{} (serial {serial}): {} ticks", r.check, r.covered);
        r.assert_passed();
        assert!(r.covered >= 39, "only {} ticks checked", r.covered);
    }
}

#[test]
fn every_property_fails_on_a_broken_trace() {
    let trace = run_rust(&stimulus(20_000, 0xdac0_0008));
    let servo = servo_run(10, false);
    for b in Breakage::ALL {
        let failed = match b.property() {
            Some(p) => !contract(&b.apply(&trace, 1_000))[p].passed(),
            None => !zero_jitter(&b.apply(&servo, 200), false).passed(),
        };
        assert!(failed, "{b:?} went unnoticed");
    }
}

/// The register table and the numbers in docs/servo_dac.md are the map's
/// and the spec's: acceptance testbenches are written from that page.
#[test]
fn the_docs_state_the_map_and_the_latency() {
    use motionhdl_model::regmap::{self, Access};
    use motionhdl_model::servo_dac::{update_latency, SAFE_CODE};
    use motionhdl_testbench::checks::servo_dac::CLOCK_HZ;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/servo_dac.md");
    let doc = std::fs::read_to_string(path).unwrap();
    let rows = doc_table_rows(&doc, "## Registers", "| word");
    let map = regmap::servo_dac(CLOCK_HZ);
    let ch = map.array("CH");
    let wanted = map
        .registers
        .iter()
        .map(|r| (r.offset.to_string(), r.name.to_string(), r))
        .chain(ch.registers.iter().map(|r| {
            let word = format!("{} + {}n", ch.offset + r.offset, ch.stride);
            (word, format!("CH[n].{}", r.name), r)
        }));
    let mut checked = 0;
    for ((word, name, r), row) in wanted.zip(&rows) {
        let access = match r.access {
            Access::ReadOnly => "RO",
            Access::WriteOnly => "WO",
            Access::ReadWrite => "RW",
            Access::WriteOneToClear => "W1C",
        };
        assert_eq!(row[..3], [word.as_str(), name.as_str(), access], "{row:?}");
        for f in &r.fields {
            let bits = match f.width {
                1 => format!("{} {}", f.name, f.lsb),
                w => format!("{} {}:{}", f.name, f.lsb + w - 1, f.lsb),
            };
            assert!(row[3].contains(&bits), "{name}: `{bits}` not in {row:?}");
        }
        if r.reset != 0 && !["INFO", "TIMING", "SERIAL"].contains(&r.name) {
            let reset = format!("reset {:#x}", r.reset);
            assert!(row[3].contains(&reset), "{name}: `{reset}` not in {row:?}");
        }
        checked += 1;
    }
    assert_eq!(rows.len(), checked, "one row per register");
    assert_eq!(checked, map.registers.len() + ch.registers.len());
    let timing = map.register("TIMING");
    let (cs, ldac) = (timing.field("CS_LOW").reset, timing.field("LDAC_LOW").reset);
    let flat = doc.split_whitespace().collect::<Vec<_>>().join(" ");
    for fact in [
        format!("({cs} and {ldac} at 50 MHz)"),
        format!("{} clocks, 460 ns at 50 MHz", update_latency(cs, ldac)),
        "**4·(W + 2) + L clocks after the start edge**".to_string(),
        format!("SAFE_CODE = {SAFE_CODE:#x}"),
    ] {
        assert!(
            flat.contains(&fact),
            "docs/servo_dac.md does not say {fact:?}"
        );
    }
}

#[test]
fn serial_contract_holds_with_every_antecedent_covered() {
    use motionhdl_testbench::checks::servo_dac::serial;
    let trace = run_rust(&stimulus(CONTRACT_CLOCKS, 0xdac0_0006));
    let reports = serial::contract(&trace);
    assert_eq!(reports.len(), serial::PROPERTIES.len());
    for (r, min) in reports.iter().zip([10_000, 500, 50]) {
        eprintln!("{}: {} cases", r.check, r.covered);
        r.assert_passed();
        assert!(r.covered >= min, "{}: only {} cases", r.check, r.covered);
    }
}

#[test]
fn every_serial_property_fails_on_a_broken_trace() {
    use motionhdl_testbench::checks::servo_dac::serial::{contract, Breakage};
    let trace = run_rust(&stimulus(20_000, 0xdac0_0008));
    assert!(contract(&trace).iter().all(|r| r.passed()));
    for b in Breakage::ALL {
        let reports = contract(&b.apply(&trace, 1_000));
        assert!(!reports[b.property()].passed(), "{b:?} went unnoticed");
    }
}
