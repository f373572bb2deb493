//! The post-synthesis netlist of a generated module: yosys's generic
//! synthesis (no vendor cells) down to single-bit gates and flip-flops,
//! written back as Verilog that Icarus simulates without yosys's simlib.
//!
//! Memories stay arrays (no `memory_map`), so the ISA bridge's two 1 K × 16
//! RAMs remain two `reg [15:0] mem [1023:0]` and the netlist stays small.
//! Everything else is gates: `techmap` lowers the word-level cells to
//! `$_AND_`/`$_OR_`/`$_XOR_`/`$_MUX_`/`$_NOT_` and `$_*DFF*_`, `abc`
//! re-maps the combinational logic, and `write_verilog` prints gates as
//! `assign` expressions and flip-flops as `always` blocks.
//!
//! Netlists are cached per module text within a process: each is made once
//! however many checks run it, and the processes of one run share them
//! through `MOTIONHDL_RUN_CACHE` ([`crate::harness::run_cached`]).

use crate::harness::tool;
use motionhdl_hdl::catalog::VerilogModule;
use std::collections::HashMap;
use std::fs;
use std::process::Command;
use std::sync::{Arc, Mutex, OnceLock};

/// The generic synthesis commands, one a line; `{top}` is the module name.
/// `tests/exports.rs` runs the same commands as its generic flow.
macro_rules! generic_synthesis {
    () => {
        "synth -top {top} -run begin:fine
opt -fast -full
techmap
opt -fast
abc
opt_clean
"
    };
}

/// [`SCRIPT`]'s synthesis: yosys's `synth` without `memory_map`, down to
/// gates.
pub const GENERIC_SYNTHESIS: &str = generic_synthesis!();

/// The yosys script; `{top}` is the module name. The design is read from
/// `in.v` and the netlist written to `net.v`.
pub const SCRIPT: &str = concat!(
    "read_verilog in.v\n",
    generic_synthesis!(),
    "check -assert
write_verilog -noattr net.v
"
);

type Entry = Arc<OnceLock<Result<String, String>>>;

fn cache() -> &'static Mutex<HashMap<String, Entry>> {
    static CACHE: OnceLock<Mutex<HashMap<String, Entry>>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The post-synthesis netlist of `module` (module name unchanged, same
/// ports), made by [`SCRIPT`]; cached by module text.
pub fn netlist(module: &VerilogModule) -> Result<String, String> {
    let entry = cache()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .entry(module.text.clone())
        .or_default()
        .clone();
    entry
        .get_or_init(|| shared(module.name, &module.text))
        .clone()
}

/// [`synthesise`] through the run's shared cache
/// ([`crate::harness::run_cached`]), keyed by script, top and text.
fn shared(top: &str, text: &str) -> Result<String, String> {
    let net = crate::harness::run_cached("netlists", &(SCRIPT, top, text), || {
        synthesise(top, text).map(String::into_bytes)
    })?;
    String::from_utf8(net).map_err(|e| format!("netlist of {top}: {e}"))
}

/// Runs [`SCRIPT`] on `text` with top module `top`, uncached.
pub fn synthesise(top: &str, text: &str) -> Result<String, String> {
    tool("yosys")?;
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = dir.path();
    fs::write(d.join("in.v"), text).map_err(|e| e.to_string())?;
    fs::write(d.join("script.ys"), SCRIPT.replace("{top}", top)).map_err(|e| e.to_string())?;
    let out = Command::new("yosys")
        .current_dir(d)
        .args(["-q", "-l", "yosys.log", "-s", "script.ys"])
        .output()
        .map_err(|e| format!("yosys: cannot start: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "yosys netlist of {top} failed ({}):\n{}\n{}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
            fs::read_to_string(d.join("yosys.log")).unwrap_or_default()
        ));
    }
    let net = fs::read_to_string(d.join("net.v")).map_err(|e| format!("net.v: {e}"))?;
    check_plain(top, &net)?;
    Ok(net)
}

/// A netlist must be plain Verilog: exactly the one module, and no instance
/// of a yosys internal cell (those would need yosys's simlib).
fn check_plain(top: &str, net: &str) -> Result<(), String> {
    let modules: Vec<&str> = net
        .lines()
        .filter_map(|l| l.strip_prefix("module "))
        .collect();
    if modules.len() != 1 || !modules[0].starts_with(&format!("{top}(")) {
        return Err(format!("netlist of {top}: modules {modules:?}"));
    }
    if let Some(l) = net.lines().find(|l| l.trim_start().starts_with("\\$")) {
        return Err(format!(
            "netlist of {top} instantiates a yosys cell (needs simlib): `{}`",
            l.trim()
        ));
    }
    Ok(())
}

/// Fault injection for the negative checks: `netlist` with the continuous
/// assignment to `lhs` inverted (`assign lhs = ~(…);`). Panics if the
/// netlist has no such assignment.
pub fn invert_assign(netlist: &str, lhs: &str) -> String {
    let prefix = format!("  assign {lhs} = ");
    let mut done = false;
    let out: Vec<String> = netlist
        .lines()
        .map(
            |l| match l.strip_prefix(&prefix).and_then(|r| r.strip_suffix(';')) {
                Some(rhs) if !done => {
                    done = true;
                    format!("{prefix}~({rhs});")
                }
                _ => l.to_string(),
            },
        )
        .collect();
    assert!(done, "no `assign {lhs} = …;` in the netlist");
    out.join("\n") + "\n"
}

/// Size of a netlist: (gate assignments, flip-flop `always` blocks).
pub fn size(netlist: &str) -> (usize, usize) {
    let assigns = netlist
        .lines()
        .filter(|l| l.trim_start().starts_with("assign "))
        .count();
    let flops = netlist
        .lines()
        .filter(|l| l.trim_start().starts_with("always "))
        .count();
    (assigns, flops)
}
