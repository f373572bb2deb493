//! The `motionhdl` binary: generate, trace, verify, configuration errors.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn motionhdl(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_motionhdl"))
        .args(args)
        .output()
        .expect("run motionhdl")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// What `generate` writes for the default configuration: the artifacts
/// and their manifest.
fn generated_files() -> Vec<(PathBuf, Vec<u8>)> {
    let files: Vec<(PathBuf, Vec<u8>)> = common::artifacts_for("")
        .iter()
        .map(|a| (a.path.clone(), a.contents.clone()))
        .collect();
    motionhdl::output::manifest::with_manifest(&files)
}

/// The binary's output and this process's `artifacts::all`, byte for byte:
/// two runs agree, so `generate` (its scenario threads too) is
/// deterministic. The binary simulates every trace itself.
#[test]
fn generate_writes_exactly_the_artifacts() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("gen");
    // Simulated here, not read from the run's trace cache.
    let o = Command::new(env!("CARGO_BIN_EXE_motionhdl"))
        .args(["generate", "--out", out.to_str().unwrap()])
        .env_remove(motionhdl_testbench::harness::RUN_CACHE_VAR)
        .output()
        .expect("run motionhdl");
    assert!(o.status.success(), "{}", stderr(&o));
    let want = generated_files();
    let mut want_paths: Vec<PathBuf> = want.iter().map(|a| a.0.clone()).collect();
    want_paths.sort();
    assert_eq!(files_under(&out), want_paths);
    for (path, contents) in &want {
        assert_eq!(
            &fs::read(out.join(path)).unwrap(),
            contents,
            "{}",
            path.display()
        );
    }
    // Nothing left beside it.
    assert_eq!(fs::read_dir(t.path()).unwrap().count(), 1);
}

#[test]
fn committed_generated_dir_is_fresh() {
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated");
    let want = generated_files();
    let mut want_paths: Vec<PathBuf> = want.iter().map(|a| a.0.clone()).collect();
    want_paths.sort();
    assert_eq!(
        files_under(&committed),
        want_paths,
        "generated/ has other files than `motionhdl generate` writes: run it and commit"
    );
    for (path, contents) in &want {
        let got = fs::read(committed.join(path)).unwrap();
        assert!(
            got == *contents,
            "generated/{} differs from a fresh `motionhdl generate`: run it and commit",
            path.display()
        );
    }
}

#[test]
fn bad_config_exits_2_names_the_value_and_writes_nothing() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("gen");
    for (text, needle) in [
        ("axes = 0\n", "axes = 0 is out of range: allowed 1..=16"),
        ("axes = 17\n", "axes = 17 is out of range: allowed 1..=16"),
        (
            "counter_width = 0\n",
            "counter_width = 0 is out of range: allowed 8..=32",
        ),
        (
            "counter_width = 33\n",
            "counter_width = 33 is out of range: allowed 8..=32",
        ),
        (
            "clock_hz = 0\n",
            "clock_hz = 0 is out of range: allowed 1000000..=400000000",
        ),
        (
            "input_filter_us = 0\n",
            "input_filter_us = 0 is out of range: allowed 1..=50000",
        ),
        (
            "input_filter_us = 50001\n",
            "input_filter_us = 50001 is out of range: allowed 1..=50000",
        ),
        (
            "gpio_inputs = 17\n",
            "gpio_inputs = 17 is out of range: allowed 0..=16",
        ),
        (
            "board = \"cyclone4-de0nano\"\n",
            "board = \"cyclone4-de0nano\" has 100 user pins; this configuration needs 147",
        ),
        ("axis = 4\n", "axis"),
    ] {
        let cfg = t.path().join("bad.toml");
        fs::write(&cfg, text).unwrap();
        let o = motionhdl(&[
            "generate",
            "--out",
            out.to_str().unwrap(),
            "--config",
            cfg.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{text}: {}", stderr(&o));
        assert!(!out.exists(), "{text}: output directory was created");
        let o = motionhdl(&[
            "trace",
            "pulse_mode_selector",
            "--out",
            out.to_str().unwrap(),
            "--config",
            cfg.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(!out.exists(), "{text}: trace file was created");
    }
    // An existing output directory is left untouched by a failed run.
    fs::create_dir_all(&out).unwrap();
    fs::write(out.join("keep.txt"), "old").unwrap();
    let cfg = t.path().join("bad.toml");
    fs::write(&cfg, "axes = 0").unwrap();
    let o = motionhdl(&[
        "generate",
        "--out",
        out.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(fs::read_to_string(out.join("keep.txt")).unwrap(), "old");
    assert_eq!(
        fs::read_dir(t.path()).unwrap().count(),
        2,
        "stray temporary files"
    );
}

#[test]
fn missing_config_file_exits_2() {
    let o = motionhdl(&[
        "generate",
        "--out",
        "/nonexistent/x",
        "--config",
        "/nonexistent/cfg.toml",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("/nonexistent/cfg.toml"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn config_changes_the_outputs() {
    let t = tempfile::tempdir().unwrap();
    let cfg = t.path().join("c.toml");
    fs::write(&cfg, "axes = 8\nclock_hz = 100_000_000\n").unwrap();
    let out = t.path().join("gen");
    // Without the traces: simulating the 8-axis controller for them takes
    // most of a minute; the clock's trace comes from `trace` below.
    let o = motionhdl(&[
        "generate",
        "--no-traces",
        "--out",
        out.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!out.join("vcd").exists(), "--no-traces wrote vcd/");
    let h = fs::read_to_string(out.join("include/motionhdl_config.h")).unwrap();
    assert!(h.contains("#define MOTIONHDL_AXES 8u"), "{h}");
    assert!(h.contains("#define MOTIONHDL_CLOCK_HZ 100000000ul"), "{h}");
    // 100 MHz: 5 ns half period in the trace.
    let vcd = t.path().join("sel.vcd");
    let o = motionhdl(&[
        "trace",
        "pulse_mode_selector",
        "--out",
        vcd.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v = fs::read_to_string(&vcd).unwrap();
    assert!(v.contains("\n#5\n"), "no 5 ns step in the 100 MHz trace");
}

/// The corners of the configuration's ranges generate: the scenario
/// traces once assumed counters wide enough for 200 steps, a clock fast
/// enough for their S-curve's jerk, and a 1 µs filter shorter than a step
/// (`generate` panicked at 8 bits, at 1 MHz and at 400 MHz).
#[test]
fn the_corners_of_the_configuration_generate() {
    for text in [
        "axes = 1\ncounter_width = 8\nclock_hz = 1_000_000\ninput_filter_us = 1\n",
        "axes = 1\ncounter_width = 32\nclock_hz = 400_000_000\n",
    ] {
        let config = motionhdl::config_file::parse(text, "corner").unwrap();
        let files = motionhdl::artifacts::all(&config);
        assert!(files.len() > 60, "{text}: {} files", files.len());
    }
}

#[test]
fn trace_writes_a_named_scenario_and_rejects_unknown_names() {
    let t = tempfile::tempdir().unwrap();
    let f = t.path().join("sel.vcd");
    let o = motionhdl(&["trace", "pulse_mode_selector", "--out", f.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let want = motionhdl_testbench::scenarios::find("pulse_mode_selector")
        .unwrap()
        .trace(&Default::default())
        .to_vcd_string();
    assert_eq!(fs::read_to_string(&f).unwrap(), want);
    let save = fs::read_to_string(t.path().join("sel.gtkw")).unwrap();
    assert!(save.contains("[dumpfile] \"sel.vcd\""), "{save}");
    assert!(!t.path().join("sel.svg").exists(), "no plot for this one");

    // A scenario with a plot writes it beside, and a foreign file there
    // stops it before any file is written.
    let f = t.path().join("loop.vcd");
    let svg = t.path().join("loop.svg");
    fs::write(&svg, "<svg>mine</svg>").unwrap();
    let o = motionhdl(&["trace", "servo_loop", "--out", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("loop.svg"), "{}", stderr(&o));
    assert_eq!(fs::read_to_string(&svg).unwrap(), "<svg>mine</svg>");
    assert!(!f.exists());
    fs::remove_file(&svg).unwrap();
    let o = motionhdl(&["trace", "servo_loop", "--out", f.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let plot = fs::read_to_string(&svg).unwrap();
    assert!(plot.starts_with(&format!("<!-- {} -->", motionhdl_hdl::banner())));
    assert!(fs::read_to_string(&f).unwrap().contains("$var wire 32"));

    let g = t.path().join("nope.vcd");
    let o = motionhdl(&["trace", "no_such_scenario", "--out", g.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no_such_scenario"), "{}", stderr(&o));
    assert!(stderr(&o).contains("pulse_mode_selector"), "{}", stderr(&o));
    assert!(!g.exists());
}

#[test]
fn verify_prints_the_coverage_table() {
    // The table of four quick groups (about 2 s): every group's checks run
    // in testbench/tests/ on their own, so here only the table is tested;
    // the pulse generator's group alone takes most of a minute.
    let mut args = vec!["verify", "--no-external"];
    let groups = motionhdl_testbench::registry::group_names();
    for g in ["selector", "ls688", "quadrature_core", "fsmc_bridge"] {
        assert!(groups.contains(&g), "no group {g} in {groups:?}");
        args.extend(["--only", g]);
    }
    let o = motionhdl(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = String::from_utf8_lossy(&o.stdout);
    let header = s.lines().next().unwrap();
    for col in ["block", "check", "covered", "expected", "result"] {
        assert!(header.contains(col), "{header}");
    }
    let ls153 = s
        .lines()
        .find(|l| l.starts_with("ls153") && l.contains("rust-hdl"))
        .expect("ls153 row");
    assert!(ls153.contains("4096      4096  pass"), "{ls153}");
    let rows = s.lines().skip(2).count();
    assert!(rows >= 10, "{rows} rows:\n{s}");
    for (block, ran) in [
        ("fsmc_bridge", true),
        ("counter_bank", false),
        ("pulse_generator", false),
    ] {
        assert_eq!(
            s.lines().any(|l| l.starts_with(block)),
            ran,
            "{block} rows:\n{s}"
        );
    }
}

#[test]
fn verify_refuses_an_unknown_group_and_lists_the_groups() {
    let o = motionhdl(&["verify", "--no-external", "--only", "counters"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("--only counters is not a group of checks"),
        "{e}"
    );
    for g in motionhdl_testbench::registry::group_names() {
        assert!(e.contains(g), "{g} not listed: {e}");
    }
    assert!(
        e.contains(motionhdl::verify::FORMAL),
        "formal not listed: {e}"
    );
    assert!(o.stdout.is_empty(), "checks ran");
}

#[test]
fn every_subcommand_has_help() {
    for (args, needle) in [
        (vec!["--help"], "generate"),
        (vec!["generate", "--help"], "--config"),
        (vec!["verify", "--help"], "covered"),
        (vec!["trace", "--help"], "pulse_mode_selector"),
    ] {
        let o = motionhdl(&args);
        assert!(o.status.success());
        assert!(
            String::from_utf8_lossy(&o.stdout).contains(needle),
            "{args:?}"
        );
    }
    let o = motionhdl(&["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
}

/// README's `verify` row names every group `--only` accepts (it had
/// drifted: `safety_io` was missing).
#[test]
fn the_readme_names_every_verify_group() {
    let readme = include_str!("../README.md");
    let row = readme
        .lines()
        .find(|l| l.contains("`motionhdl verify [--no-external]"))
        .expect("README has the verify row");
    let groups = motionhdl_testbench::registry::group_names();
    for g in groups.into_iter().chain([motionhdl::verify::FORMAL]) {
        assert!(
            row.contains(&format!("`{g}`")),
            "README's verify row lacks `{g}`"
        );
    }
}
