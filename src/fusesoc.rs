//! The FuseSoC core description (CAPI2) of the generated gateware:
//! `generated/motionhdl.core`, with its paths relative to `generated/`.

use crate::board;
use motionhdl_hdl::{banner, VERSION};
use motionhdl_model::Config;

/// File name inside the output directory.
pub const FILE_NAME: &str = "motionhdl.core";

/// The core for `config`; `constraints` are the constraint files written
/// into `constraints/` (see [`crate::constraints::files`]).
pub fn core(config: &Config, constraints: &[String]) -> String {
    let has = |ext: &str| constraints.iter().find(|n| n.ends_with(ext));
    let mut s = String::new();
    // FuseSoC reads the first word of the first line as the format
    // (`CAPI=2:`); the banner follows it there as a YAML comment.
    s.push_str(&format!("CAPI=2: # {}\n", banner()));
    s.push_str(&format!(
        "# FuseSoC core of the motionhdl gateware ({} axes, {}-bit counters, {} Hz, isa_ram = \"{}\").\n\
         # Paths are relative to this file (generated/). `fusesoc --cores-root generated run\n\
         # --target=lint motionhdl` lints; --target=synth builds for the iCE40-HX8K breakout.\n",
        config.axes(),
        config.counter_width(),
        config.clock_hz(),
        config.isa_ram().name()
    ));
    s.push_str(&format!("name: ::motionhdl:{VERSION}\n"));
    s.push_str("description: Multi-axis motion controller gateware (FSMC and ISA bridges, encoder counter bank)\n\n");
    s.push_str("filesets:\n");
    s.push_str("  rtl:\n    files:\n");
    s.push_str("      - verilog/motion_controller.v\n");
    s.push_str(&format!("      - verilog/{}.v\n", board::MODULE));
    s.push_str("    file_type: verilogSource\n");
    let fileset = |s: &mut String, name: &str, file: &str, ty: &str| {
        s.push_str(&format!(
            "  {name}:\n    files:\n      - constraints/{file}\n    file_type: {ty}\n"
        ));
    };
    if let Some(f) = has(".pcf") {
        fileset(&mut s, "ice40_pins", f, "PCF");
    }
    if let Some(f) = has(".lpf") {
        fileset(&mut s, "ecp5_pins", f, "LPF");
    }
    if let (Some(q), Some(d)) = (has(".qsf"), has(".sdc")) {
        s.push_str(&format!(
            "  quartus_constraints:\n    files:\n      - constraints/{q}: {{file_type: tclSource}}\n      - constraints/{d}: {{file_type: SDC}}\n"
        ));
    }
    s.push_str(&format!(
        "\ntargets:\n  default:\n    filesets: [rtl]\n    toplevel: {top}\n\n  lint:\n    default_tool: verilator\n    filesets: [rtl]\n    tools:\n      verilator:\n        mode: lint-only\n        verilator_options: [-Wall]\n    toplevel: {top}\n",
        top = board::MODULE
    ));
    let mhz = config.clock_hz() / 1_000_000;
    if has(".pcf").is_some() {
        s.push_str(&format!(
            "\n  synth:\n    default_tool: icestorm\n    filesets: [rtl, ice40_pins]\n    tools:\n      icestorm:\n        pnr: next\n        nextpnr_options: [--hx8k, --package, ct256, --freq, \"{mhz}\"]\n    toplevel: {top}\n",
            top = board::MODULE
        ));
    }
    if has(".lpf").is_some() {
        s.push_str(&format!(
            "\n  synth_ecp5:\n    default_tool: trellis\n    filesets: [rtl, ecp5_pins]\n    tools:\n      trellis:\n        nextpnr_options: [--25k, --package, CABGA256, --freq, \"{mhz}\"]\n    toplevel: {top}\n",
            top = board::MODULE
        ));
    }
    if has(".qsf").is_some() {
        s.push_str(&format!(
            "\n  synth_quartus:\n    default_tool: quartus\n    filesets: [rtl, quartus_constraints]\n    tools:\n      quartus:\n        family: Cyclone IV E\n        device: EP4CE22F17C6\n    toplevel: {top}\n",
            top = board::MODULE
        ));
    }
    s
}
