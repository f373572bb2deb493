//! The generated FuseSoC core run by FuseSoC itself (Edalize's flow API):
//! the committed `generated/motionhdl.core` lints with its default
//! target, and a one-axis build goes through `lint` and `synth` to an
//! iCE40 bitstream (the default top's place and route takes minutes; the
//! one-axis top is the same generator's output, about a minute).

mod common;

use common::run;
use motionhdl_testbench::harness::{require_tools, tool};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// FuseSoC's work directory for `target` under the build root.
fn work(target: &str) -> PathBuf {
    Path::new(&format!("motionhdl_{}", motionhdl_hdl::VERSION)).join(target)
}

/// `fusesoc --cores-root CORES run --build-root BUILD [--target T]
/// motionhdl`: its output, panicking with it when FuseSoC fails.
fn fusesoc(cores: &Path, build: &Path, target: Option<&str>) -> String {
    // install-tools puts FuseSoC in the tools' venv, not on PATH.
    let fusesoc = tool("fusesoc").expect("fusesoc: the test checked it first");
    let mut cmd = Command::new(fusesoc);
    cmd.arg("--cores-root")
        .arg(cores)
        .arg("run")
        .arg("--build-root")
        .arg(build);
    if let Some(t) = target {
        cmd.args(["--target", t]);
    }
    let (ok, out, err) = run(cmd.arg("motionhdl"));
    let text = format!("{out}{err}");
    assert!(ok, "fusesoc run --target {target:?} failed:\n{text}");
    // The flow API: no deprecated tool-API warning, no missing flow.
    assert!(
        !text.contains("deprecated") && !text.contains("No flow or tool"),
        "fusesoc --target {target:?}:\n{text}"
    );
    text
}

/// `fusesoc run motionhdl` on the committed core: the default target is
/// the lint flow (Verilator `--lint-only -Wall`) on the board top.
#[test]
fn default_target_lints_the_committed_core() {
    if require_tools(&["fusesoc", "verilator"]).is_none() {
        return;
    }
    let build = tempfile::tempdir().unwrap();
    let text = fusesoc(&root().join("generated"), build.path(), None);
    assert!(text.contains("verilator"), "no Verilator run:\n{text}");
    assert!(build.path().join(work("default")).is_dir());
}

/// A one-axis configuration through `lint` and `synth`: yosys, nextpnr
/// (seed 1, 50 MHz) and icepack give a bitstream whose timing passed.
#[test]
fn one_axis_core_lints_and_synthesises_to_a_bitstream() {
    if require_tools(&["fusesoc", "verilator", "yosys", "nextpnr-ice40", "icepack"]).is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("one.toml");
    std::fs::write(&config, "axes = 1\n").unwrap();
    let cores = dir.path().join("generated");
    let (ok, out, err) = run(Command::new(env!("CARGO_BIN_EXE_motionhdl"))
        .args(["generate", "--no-traces", "--config"])
        .arg(&config)
        .arg("--out")
        .arg(&cores));
    assert!(ok, "generate:\n{out}{err}");
    let build = dir.path().join("build");
    fusesoc(&cores, &build, Some("lint"));
    let text = fusesoc(&cores, &build, Some("synth"));
    let bin = build
        .join(work("synth"))
        .join(format!("motionhdl_{}.bin", motionhdl_hdl::VERSION));
    let size = std::fs::metadata(&bin)
        .unwrap_or_else(|e| panic!("no bitstream {}: {e}\n{text}", bin.display()))
        .len();
    // An iCE40-HX8K bitstream is 135 100 bytes.
    assert!(size > 100_000, "bitstream of {size} bytes");
    let fmax: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("Max frequency for clock"))
        .collect();
    assert!(
        !fmax.is_empty() && fmax.iter().all(|l| l.contains("PASS at 50.00 MHz")),
        "timing: {fmax:?}"
    );
    assert!(text.contains("--seed 1"), "nextpnr not run with seed 1");
    println!("{}", fmax.last().unwrap());
}
