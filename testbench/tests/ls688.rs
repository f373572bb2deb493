//! 74LS688: every one of the 2^17 inputs, each check asserting its coverage.

use motionhdl_testbench::checks::ls688;
use motionhdl_testbench::verilog_sim::Simulator;

#[test]
fn ls688_every_input_rust_hdl_vs_model() {
    let r = ls688::ls688_hdl();
    assert_eq!(r.expected, 131_072);
    r.assert_passed();
}

#[test]
fn ls688_generated_verilog_in_icarus() {
    let r = ls688::ls688_verilog(Simulator::Icarus);
    assert_eq!(r.expected, 131_072);
    r.assert_passed();
}

#[test]
fn ls688_generated_verilog_in_verilator() {
    let r = ls688::ls688_verilog(Simulator::Verilator);
    assert_eq!(r.expected, 131_072);
    r.assert_passed();
}
