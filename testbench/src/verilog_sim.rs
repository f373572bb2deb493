//! Runs exported Verilog in Icarus Verilog or Verilator, driven by a vector
//! testbench written here, so the same stimulus the rust-hdl block sees goes
//! through the generated files.
//!
//! Each vector sets every input; the testbench waits for the logic to settle,
//! prints every output, then (for clocked designs) applies one rising edge.
//! The rust-hdl side does the same: set inputs, settle, read, clock.

use crate::harness::{tool, CheckReport};
use motionhdl_hdl::catalog::VerilogModule;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// A simulator for generated Verilog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simulator {
    Icarus,
    /// Verilator 5 with default options (`--binary`; no `-fno-inline`).
    Verilator,
}

impl Simulator {
    pub fn name(self) -> &'static str {
        match self {
            Simulator::Icarus => "Icarus Verilog",
            Simulator::Verilator => "Verilator",
        }
    }
    /// The executables this simulator needs.
    pub fn tools(self) -> &'static [&'static str] {
        match self {
            Simulator::Icarus => &["iverilog", "vvp"],
            Simulator::Verilator => &["verilator"],
        }
    }
    /// `Err(reason)` when a needed executable is missing.
    pub fn available(self) -> Result<(), String> {
        for t in self.tools() {
            tool(t)?;
        }
        Ok(())
    }
}

/// Which Verilog text of a block a check simulates.
#[derive(Clone, Copy, Debug)]
pub enum Source {
    /// The exporter's output, as `motionhdl generate` writes it.
    Generated,
    /// The post-synthesis yosys netlist of that text ([`crate::netlist`]).
    Netlist,
    /// The netlist after a text substitution: fault injection, to show that
    /// a netlist comparison can fail.
    MutatedNetlist(fn(&str) -> String),
}

impl Source {
    pub fn name(self) -> &'static str {
        match self {
            Source::Generated => "generated Verilog",
            Source::Netlist => "post-synthesis yosys netlist",
            Source::MutatedNetlist(_) => "mutated post-synthesis netlist",
        }
    }

    /// The Verilog text of `module` this source stands for.
    pub fn text(self, module: &VerilogModule) -> Result<String, String> {
        match self {
            Source::Generated => Ok(module.text.clone()),
            Source::Netlist => crate::netlist::netlist(module),
            Source::MutatedNetlist(f) => crate::netlist::netlist(module).map(|t| f(&t)),
        }
    }

    /// `Err(reason)` when a needed executable is missing.
    pub fn available(self) -> Result<(), String> {
        match self {
            Source::Generated => Ok(()),
            Source::Netlist | Source::MutatedNetlist(_) => tool("yosys").map(|_| ()),
        }
    }
}

/// A simulator and the Verilog it runs. A bare [`Simulator`] converts to
/// the generated file in that simulator.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    pub sim: Simulator,
    pub source: Source,
}

impl Target {
    /// The post-synthesis netlist in `sim`.
    pub fn netlist(sim: Simulator) -> Self {
        Self {
            sim,
            source: Source::Netlist,
        }
    }

    /// "generated Verilog in Icarus Verilog", for check names.
    pub fn describe(self) -> String {
        format!("{} in {}", self.source.name(), self.sim.name())
    }

    /// `Err(reason)` when a needed executable is missing.
    pub fn available(self) -> Result<(), String> {
        self.sim.available()?;
        self.source.available()
    }

    /// The text to simulate for `module`.
    pub fn text(self, module: &VerilogModule) -> Result<String, String> {
        self.source.text(module)
    }
}

impl From<Simulator> for Target {
    fn from(sim: Simulator) -> Self {
        Self {
            sim,
            source: Source::Generated,
        }
    }
}

/// A port of the design under test.
#[derive(Clone, Debug)]
pub struct Port {
    pub name: String,
    pub width: u32,
}

impl Port {
    pub fn new(name: &str, width: u32) -> Self {
        assert!((1..=64).contains(&width));
        Self {
            name: name.into(),
            width,
        }
    }
}

/// The ports `names` of `module`, in that order (the order the vectors
/// pack them in), each with the width the exporter reports for it, so no
/// testbench retypes a port's width. Panics on a name the module lacks.
pub fn ports_of(module: &VerilogModule, names: &[&str]) -> Vec<Port> {
    names
        .iter()
        .map(|name| {
            let p = module
                .ports
                .iter()
                .find(|p| p.name == *name)
                .unwrap_or_else(|| panic!("module {} has no port `{name}`", module.name));
            Port::new(name, p.width)
        })
        .collect()
}

/// For a testbench that drives a design itself (an in-simulator stimulus
/// generator): one net per port named as the port (`reg` for inputs, which
/// the testbench drives; `wire` for outputs) and the instance `dut`
/// connected by name, all from the exporter's port list, so no testbench
/// retypes a port.
pub fn dut_instance(module: &VerilogModule) -> String {
    use motionhdl_hdl::ports::PortDir;
    let mut t = String::new();
    for p in &module.ports {
        let kind = match p.dir {
            PortDir::Input => "reg",
            PortDir::Output | PortDir::InOut => "wire",
        };
        t.push_str(&net_declaration(kind, p.width, &p.name, ""));
    }
    t.push_str(&named_instance(module.name, "dut", &module.ports));
    t
}

/// One testbench net: `kind` (`reg` or `wire`), its range unless one bit
/// wide, and `init` (e.g. " = 0") after the name.
pub fn net_declaration(kind: &str, width: u32, name: &str, init: &str) -> String {
    match width {
        1 => format!("    {kind} {name}{init};\n"),
        w => format!("    {kind} [{}:0] {name}{init};\n", w - 1),
    }
}

/// Instance `inst` of `module`, every port connected to the net of its
/// own name.
pub fn named_instance(module: &str, inst: &str, ports: &[motionhdl_hdl::ports::Port]) -> String {
    let conns: Vec<String> = ports.iter().map(|p| format!(".{0}({0})", p.name)).collect();
    format!(
        "    {module} {inst} (\n        {}\n    );\n",
        conns.join(",\n        ")
    )
}

/// What to simulate.
pub struct Design<'a> {
    /// Module name of the design under test.
    pub top: &'a str,
    /// Verilog source text of the design (one or more modules).
    pub source: &'a str,
    pub inputs: Vec<Port>,
    pub outputs: Vec<Port>,
    /// Clock input, if the design is clocked (not listed in `inputs`).
    pub clock: Option<&'a str>,
}

fn testbench(design: &Design, vectors: usize) -> String {
    let in_width: u32 = design.inputs.iter().map(|p| p.width).sum();
    let mut t = String::new();
    let _ = writeln!(t, "`timescale 1ns / 1ps\n`default_nettype none");
    let _ = writeln!(t, "module motionhdl_tb;");
    let _ = writeln!(
        t,
        "    reg [{}:0] vectors [0:{}];",
        in_width - 1,
        vectors - 1
    );
    let _ = writeln!(t, "    reg [{}:0] v;", in_width - 1);
    let _ = writeln!(t, "    integer i;");
    if let Some(c) = design.clock {
        let _ = writeln!(t, "    reg {c};");
    }
    for o in &design.outputs {
        let _ = writeln!(t, "    wire [{}:0] out_{};", o.width - 1, o.name);
    }
    let _ = writeln!(t, "    {} dut (", design.top);
    let mut conns = Vec::new();
    if let Some(c) = design.clock {
        conns.push(format!("        .{c}({c})"));
    }
    // First input in the most significant bits, as in the hex file.
    let mut hi = in_width;
    for p in &design.inputs {
        let lo = hi - p.width;
        conns.push(format!("        .{}(v[{}:{}])", p.name, hi - 1, lo));
        hi = lo;
    }
    for o in &design.outputs {
        conns.push(format!("        .{}(out_{})", o.name, o.name));
    }
    let _ = writeln!(t, "{}\n    );", conns.join(",\n"));
    let fmt: Vec<&str> = design.outputs.iter().map(|_| "%h").collect();
    let args: Vec<String> = design
        .outputs
        .iter()
        .map(|o| format!("out_{}", o.name))
        .collect();
    let _ = writeln!(t, "    initial begin");
    if let Some(c) = design.clock {
        let _ = writeln!(t, "        {c} = 1'b0;");
    }
    let _ = writeln!(t, "        $readmemh(\"vectors.hex\", vectors);");
    let _ = writeln!(t, "        for (i = 0; i < {vectors}; i = i + 1) begin");
    let _ = writeln!(t, "            v = vectors[i];");
    let _ = writeln!(t, "            #4;");
    let _ = writeln!(
        t,
        "            $display(\"OUT {}\", {});",
        fmt.join(" "),
        args.join(", ")
    );
    if let Some(c) = design.clock {
        let _ = writeln!(
            t,
            "            {c} = 1'b1;\n            #5;\n            {c} = 1'b0;\n            #1;"
        );
    } else {
        let _ = writeln!(t, "            #6;");
    }
    let _ = writeln!(t, "        end\n        $finish;\n    end\nendmodule");
    t
}

/// Compiles `files` (already in `dir`) with top module `top` in `sim` and
/// runs the result there. `strict`: Icarus with `-Wall`, and Verilator
/// warnings fatal (its default). Returns stdout and how long the run took,
/// compilation excluded.
pub fn build_and_run(
    sim: Simulator,
    dir: &Path,
    top: &str,
    files: &[&str],
    strict: bool,
) -> Result<(String, Duration), String> {
    sim.available()?;
    match sim {
        Simulator::Icarus => {
            let mut c = Command::new("iverilog");
            c.current_dir(dir).arg("-g2012");
            if strict {
                c.arg("-Wall");
            }
            run(c.args(["-o", "sim.vvp", "-s", top]).args(files), "iverilog")?;
            let started = Instant::now();
            let out = run(
                Command::new("vvp").current_dir(dir).args(["-n", "sim.vvp"]),
                "vvp",
            )?;
            Ok((out, started.elapsed()))
        }
        Simulator::Verilator => {
            let mut c = Command::new("verilator");
            crate::harness::cache_verilator_build(&mut c);
            c.current_dir(dir).args(["--binary", "-j", "2"]);
            if !strict {
                c.arg("-Wno-fatal");
            }
            run(
                c.args(["--top-module", top, "-Mdir", "obj", "-o", "sim"])
                    .args(files),
                "verilator",
            )?;
            let started = Instant::now();
            let out = run(
                Command::new(dir.join("obj").join("sim")).current_dir(dir),
                "verilated simulation",
            )?;
            Ok((out, started.elapsed()))
        }
    }
}

pub(crate) fn run(cmd: &mut Command, what: &str) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("{what}: cannot start: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    if !out.status.success() {
        return Err(format!(
            "{what} failed ({}):\n{}\n{}",
            out.status,
            stdout,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(stdout)
}

/// Runs `vectors` (one value per input, in `design.inputs` order) through
/// the design and returns one value per output per vector.
pub fn run_vectors(
    sim: Simulator,
    design: &Design,
    vectors: &[Vec<u64>],
) -> Result<Vec<Vec<u64>>, String> {
    sim.available()?;
    assert!(!vectors.is_empty());
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = dir.path();
    fs::write(d.join("dut.v"), design.source).map_err(|e| e.to_string())?;
    fs::write(d.join("tb.v"), testbench(design, vectors.len())).map_err(|e| e.to_string())?;
    let mut hex = String::new();
    for v in vectors {
        assert_eq!(v.len(), design.inputs.len(), "one value per input");
        for (p, x) in design.inputs.iter().zip(v) {
            assert!(
                p.width == 64 || *x < (1u64 << p.width),
                "{} = {x} exceeds {} bits",
                p.name,
                p.width
            );
        }
        let fields: Vec<(u32, u64)> = design
            .inputs
            .iter()
            .map(|p| p.width)
            .zip(v.iter().copied())
            .collect();
        hex.push_str(&pack_hex(&fields));
        hex.push('\n');
    }
    fs::write(d.join("vectors.hex"), hex).map_err(|e| e.to_string())?;
    let (stdout, _) = build_and_run(sim, d, "motionhdl_tb", &["tb.v", "dut.v"], true)?;
    parse_outputs(&stdout, design.outputs.len(), vectors.len())
}

/// `fields` (width, value), first most significant, as one hex word of
/// any width (a u128 once silently dropped the top bits of a 131-bit
/// vector).
pub fn pack_hex(fields: &[(u32, u64)]) -> String {
    let mut bits: Vec<bool> = Vec::new();
    for &(width, x) in fields {
        debug_assert!(
            width == 64 || x < (1u64 << width),
            "{x} exceeds {width} bits"
        );
        bits.extend((0..width).rev().map(|b| x >> b & 1 == 1));
    }
    let pad = (4 - bits.len() % 4) % 4;
    let padded: Vec<bool> = std::iter::repeat_n(false, pad).chain(bits).collect();
    padded
        .chunks(4)
        .map(|nibble| {
            let d = nibble.iter().fold(0u32, |a, &b| a << 1 | u32::from(b));
            char::from_digit(d, 16).expect("a hex digit")
        })
        .collect()
}

fn parse_outputs(stdout: &str, n_out: usize, n_vec: usize) -> Result<Vec<Vec<u64>>, String> {
    let rows: Vec<Vec<u64>> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("OUT "))
        .map(|l| {
            l.split_whitespace()
                .map(|x| {
                    u64::from_str_radix(x, 16)
                        .map_err(|_| format!("bad output value `{x}` (X or Z?)"))
                })
                .collect::<Result<Vec<u64>, String>>()
        })
        .collect::<Result<_, _>>()?;
    if rows.len() != n_vec || rows.iter().any(|r| r.len() != n_out) {
        return Err(format!(
            "expected {n_vec} rows of {n_out} outputs, got:\n{stdout}"
        ));
    }
    Ok(rows)
}

/// Writes `files` (name, text) to a scratch directory, runs testbench
/// `top` (the first file) in `sim` and parses its `SUMS a b ...` line: the
/// checksums, and how long the simulation ran (compilation excluded).
pub fn run_for_sums(
    sim: Simulator,
    files: &[(&str, String)],
    top: &str,
) -> Result<(Vec<u32>, Duration), String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = dir.path();
    for (name, text) in files {
        std::fs::write(d.join(name), text).map_err(|e| e.to_string())?;
    }
    let names: Vec<&str> = files.iter().map(|(n, _)| *n).collect();
    let (out, elapsed) = build_and_run(sim, d, top, &names, false)?;
    let line = out
        .lines()
        .find_map(|l| l.strip_prefix("SUMS "))
        .ok_or_else(|| format!("no SUMS line in:\n{out}"))?;
    let sums = line
        .split_whitespace()
        .map(|x| x.parse().map_err(|e| format!("{x}: {e}")))
        .collect::<Result<_, _>>()?;
    Ok((sums, elapsed))
}

/// A run that failed: skipped when a tool is missing, else a failure.
pub fn sim_failure(r: CheckReport, t: Target, err: String) -> CheckReport {
    match t.available() {
        Err(why) => r.skip(why),
        Ok(()) => {
            let mut r = r;
            r.failures
                .push(format!("{} run failed: {err}", t.describe()));
            r
        }
    }
}

/// Runs one vector per input through `design` in `sim` and records one case
/// per input: `mismatch` gets the input and its outputs and describes any
/// difference from the model.
pub fn compare_vectors<I>(
    r: CheckReport,
    t: Target,
    design: &Design,
    inputs: &[I],
    encode: impl Fn(&I) -> Vec<u64>,
    mismatch: impl Fn(&I, &[u64]) -> Option<String>,
) -> CheckReport {
    let vectors: Vec<Vec<u64>> = inputs.iter().map(encode).collect();
    match run_vectors(t.sim, design, &vectors) {
        Err(e) => sim_failure(r, t, e),
        Ok(out) => {
            let mut r = r;
            for (i, o) in inputs.iter().zip(out) {
                r.case(mismatch(i, &o));
            }
            r
        }
    }
}

/// Runs one row per clock through the clocked `design` (an idle row more
/// shows the last edge's outputs) and compares each clock's outputs with
/// `want`, one case per clock; `describe(k)` names clock k's inputs.
pub fn compare_clocked(
    r: CheckReport,
    t: Target,
    design: &Design,
    mut rows: Vec<Vec<u64>>,
    want: &[Vec<u64>],
    describe: impl Fn(usize) -> String,
) -> CheckReport {
    let width = rows.first().map_or(0, Vec::len);
    rows.push(vec![0; width]);
    match run_vectors(t.sim, design, &rows) {
        Err(e) => sim_failure(r, t, e),
        Ok(out) => {
            let mut r = r;
            for (k, expect) in want.iter().enumerate() {
                let got = &out[k + 1];
                r.case((got[..] != expect[..]).then(|| {
                    format!(
                        "clock {k} {}: Verilog {got:?}, model {expect:?}",
                        describe(k)
                    )
                }));
            }
            r
        }
    }
}
