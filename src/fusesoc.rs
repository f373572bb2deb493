//! The FuseSoC core description (CAPI2) of the generated gateware:
//! `generated/motionhdl.core`, with its paths relative to `generated/`.

use crate::board;
use motionhdl_hdl::{banner, VERSION};
use motionhdl_model::Config;

/// File name inside the output directory.
pub const FILE_NAME: &str = "motionhdl.core";

/// The nextpnr seed of the synthesis targets.
pub const SEED: u32 = 1;

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
         # motionhdl` lints (the default target, as --target=lint); --target=synth builds a\n\
         # bitstream for the iCE40-HX8K breakout, --target=synth_ecp5 for the ECP5-25K.\n",
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
    // Edalize's flow API (the tool API is deprecated): `default` is the
    // lint flow, so a bare `fusesoc run motionhdl` does something useful;
    // place and route use seed 1, the seed of docs/benchmarks.md's tables.
    let lint = format!(
        "    flow: lint\n    flow_options:\n      tool: verilator\n      verilator_options: [-Wall]\n    \
         filesets: [rtl]\n    toplevel: {}\n",
        board::MODULE
    );
    s.push_str(&format!("\ntargets:\n  default:\n{lint}\n  lint:\n{lint}"));
    let mhz = config.clock_hz() / 1_000_000;
    let pnr = |s: &mut String, target: &str, flow: &str, pins: &str, device: &str| {
        s.push_str(&format!(
            "\n  {target}:\n    flow: {flow}\n    flow_options:\n      \
             nextpnr_options: [{device}, --freq, \"{mhz}\", --seed, \"{SEED}\"]\n    \
             filesets: [rtl, {pins}]\n    toplevel: {top}\n",
            top = board::MODULE
        ));
    };
    if has(".pcf").is_some() {
        pnr(
            &mut s,
            "synth",
            "icestorm",
            "ice40_pins",
            "--hx8k, --package, ct256",
        );
    }
    if has(".lpf").is_some() {
        pnr(
            &mut s,
            "synth_ecp5",
            "trellis",
            "ecp5_pins",
            "--25k, --package, CABGA256",
        );
    }
    // Edalize 0.6 has no Quartus flow: this one target keeps the tool API.
    if has(".qsf").is_some() {
        s.push_str(&format!(
            "\n  synth_quartus:\n    default_tool: quartus\n    filesets: [rtl, quartus_constraints]\n    tools:\n      quartus:\n        family: Cyclone IV E\n        device: EP4CE22F17C6\n    toplevel: {top}\n",
            top = board::MODULE
        ));
    }
    s
}
