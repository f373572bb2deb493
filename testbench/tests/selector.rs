//! 74LS153 and pulse-mode selector: exhaustive checks, each asserting its coverage.

use motionhdl_testbench::checks::{ls153, pulse_mode_selector};
use motionhdl_testbench::verilog_sim::Simulator;

#[test]
fn ls153_every_input_rust_hdl_vs_model() {
    let r = ls153::ls153_hdl();
    assert_eq!(r.expected, 4096);
    r.assert_passed();
}

#[test]
fn selector_model_forms_agree_with_seed_table() {
    for r in pulse_mode_selector::selector_model_forms() {
        assert_eq!(r.expected, 8);
        r.assert_passed();
    }
}

#[test]
fn selector_rust_hdl_vs_seed_table_and_chip_wiring() {
    let r = pulse_mode_selector::selector_hdl();
    assert_eq!(r.expected, 8);
    r.assert_passed();
}

#[test]
fn registered_selector_every_state_and_input() {
    let r = pulse_mode_selector::registered_hdl();
    assert_eq!(r.expected, 64);
    r.assert_passed();
}

#[test]
fn generated_verilog_in_icarus() {
    for r in [
        ls153::ls153_verilog(Simulator::Icarus),
        pulse_mode_selector::selector_verilog(Simulator::Icarus),
        pulse_mode_selector::registered_verilog(Simulator::Icarus),
    ] {
        r.assert_passed();
    }
}

#[test]
fn generated_verilog_in_verilator() {
    for r in [
        ls153::ls153_verilog(Simulator::Verilator),
        pulse_mode_selector::selector_verilog(Simulator::Verilator),
        pulse_mode_selector::registered_verilog(Simulator::Verilator),
    ] {
        r.assert_passed();
    }
}
