//! The servo DAC block (docs/servo_dac.md): against its model every clock
//! in rust-hdl, Icarus, Verilator and the post-synthesis netlist, its
//! contract on the DAC pins over a long run and its zero-jitter servo
//! loop, each property shown able to fail.

use motionhdl_testbench::checks::servo_dac::contract::{
    contract, servo_run, zero_jitter, Breakage, PROPERTIES,
};
use motionhdl_testbench::checks::servo_dac::{random_rust, random_verilog, run_rust, stimulus};
use motionhdl_testbench::verilog_sim::{Simulator, Target};

#[test]
fn block_against_model_in_rust_hdl() {
    random_rust(100_000, 0xdac0_0001).assert_passed();
}

#[test]
fn generated_verilog_against_model() {
    random_verilog(Simulator::Icarus, 50_000, 0xdac0_0002).assert_passed();
    random_verilog(Simulator::Verilator, 500_000, 0xdac0_0003).assert_passed();
}

#[test]
fn netlist_against_model() {
    random_verilog(Target::netlist(Simulator::Icarus), 20_000, 0xdac0_0004).assert_passed();
    random_verilog(Target::netlist(Simulator::Verilator), 100_000, 0xdac0_0005).assert_passed();
}

/// Clocks of the contract run, and how often each property's antecedent
/// must hold in it (so none passes by never being tested).
const CONTRACT_CLOCKS: usize = 100_000;
const MIN_COVERED: [u64; 4] = [100_000, 10_000, 5_000, 500];

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
    let trace = servo_run(40);
    let r = zero_jitter(&trace);
    eprintln!("{}: {} ticks", r.check, r.covered);
    r.assert_passed();
    assert!(r.covered >= 39, "only {} ticks checked", r.covered);
}

#[test]
fn every_property_fails_on_a_broken_trace() {
    let trace = run_rust(&stimulus(20_000, 0xdac0_0008));
    let servo = servo_run(10);
    for b in Breakage::ALL {
        let failed = match b.property() {
            Some(p) => !contract(&b.apply(&trace, 1_000))[p].passed(),
            None => !zero_jitter(&b.apply(&servo, 200)).passed(),
        };
        assert!(failed, "{b:?} went unnoticed");
    }
}
