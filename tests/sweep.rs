//! `motionhdl synth --sweep`: a one-row sweep through yosys and nextpnr
//! written into a document that keeps everything else it holds, and bad
//! arguments refused before anything runs.

use motionhdl::sweep::{BEGIN, END};
use motionhdl_testbench::harness::require_tool;
use std::process::{Command, Output};

fn motionhdl(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_motionhdl"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn a_sweep_writes_its_table_between_the_markers() {
    if require_tool("yosys").is_none() || require_tool("nextpnr-ice40").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let doc = dir.path().join("benchmarks.md");
    let before =
        format!("# Benchmarks\n\nhand-written text\n\n{BEGIN}\nstale table\n{END}\n\nmore text\n");
    std::fs::write(&doc, &before).unwrap();
    let out = motionhdl(&[
        "synth",
        "--sweep",
        "--axes",
        "1",
        "--seeds",
        "1",
        "--targets",
        "ice40-hx8k",
        "--no-blocks",
        "--write",
        doc.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let after = std::fs::read_to_string(&doc).unwrap();
    assert!(
        after.starts_with("# Benchmarks\n\nhand-written text\n\n"),
        "{after}"
    );
    assert!(after.ends_with(&format!("{END}\n\nmore text\n")), "{after}");
    assert!(!after.contains("stale table"));
    assert!(
        after.contains("Measured at commit ")
            && after.contains(
                "by `motionhdl synth --sweep --axes 1 --seeds 1 --targets ice40-hx8k --no-blocks`"
            )
    );
    // The row: routed, with the one-axis top's numbers (12 RAM blocks: the
    // ISA RAM's 8, the axis's segment FIFO's 2 and its jerk ring's 2) and
    // an Fmax.
    let row = after
        .lines()
        .find(|l| l.starts_with("| ice40-hx8k | board top, 1 axis | 1 |"))
        .unwrap_or_else(|| panic!("no row in\n{after}"));
    let cols: Vec<&str> = row.split('|').map(str::trim).collect();
    assert!(cols[4].ends_with(" / 7680"), "{row}");
    assert_eq!(cols[8], "12", "{row}");
    assert!(
        cols[10].ends_with("(50)") || cols[10].ends_with("(50, misses it)"),
        "{row}"
    );
    // The printed table is the written one.
    assert!(stdout.contains(row), "{stdout}");
}

#[test]
fn bad_sweep_arguments_exit_2_and_touch_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let doc = dir.path().join("b.md");
    std::fs::write(&doc, "keep\n").unwrap();
    let d = doc.to_str().unwrap();
    for (args, says) in [
        (vec!["--axes", "0"], "--axes: `0` is not a number in 1..=16"),
        (
            vec!["--axes", "4,17"],
            "--axes: `17` is not a number in 1..=16",
        ),
        (
            vec!["--seeds", "3000000000"],
            "--seeds: `3000000000` is not a number in 0..=2147483647",
        ),
        (
            vec!["--targets", "ice40"],
            "--targets: `ice40` is not a target",
        ),
    ] {
        let mut all = vec!["synth", "--sweep", "--write", d];
        all.extend(args);
        let out = motionhdl(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{all:?}: {err}");
        assert!(err.contains(says), "{all:?}: {err}");
    }
    // A document whose markers are broken is refused before any run.
    std::fs::write(&doc, format!("{END}\n{BEGIN}\n")).unwrap();
    let out = motionhdl(&["synth", "--sweep", "--write", d]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("out of order"));
    assert_eq!(
        std::fs::read_to_string(&doc).unwrap(),
        format!("{END}\n{BEGIN}\n")
    );
    // --sweep's options need --sweep; --sweep takes no --seed.
    for args in [
        vec!["synth", "--axes", "4"],
        vec!["synth", "--sweep", "--seed", "2"],
    ] {
        assert_eq!(motionhdl(&args).status.code(), Some(2), "{args:?}");
    }
}
