//! `motionhdl_regs_selftest.c`, the C self-test of the MCU header: its
//! number of checks against the table, and in gcc it passes on the
//! generated header (C99 and C11) and fails on a corrupted one. The tests
//! need gcc: under CI a missing gcc fails them; elsewhere they are skipped.

mod common;

use common::regmap::{default_map, expected_macros, other_configs, table_counts};
use common::run;
use motionhdl::regmap_export::{c_header, selftest};
use motionhdl_model::regmap::{mcu_map, BusMap};
use motionhdl_model::Config;
use motionhdl_testbench::harness::require_tool;
use std::fs;
use std::path::Path;
use std::process::Command;

/// The self-test's number of checks, counted here from the table: the
/// macros, every struct member's offset and every struct's size, and each
/// register's address via the window struct and via the offset macros.
fn expected_checks(map: &BusMap) -> usize {
    let (regs, _) = table_counts(map);
    let functions: usize = map
        .blocks
        .iter()
        .flat_map(|b| b.arrays.iter())
        .map(|a| a.count as usize)
        .sum();
    let mut structs = 0;
    for b in &map.blocks {
        structs += b.registers.len() + 1;
        for a in &b.arrays {
            structs += a.registers.len() + 2;
        }
    }
    structs += map.blocks.len() + 2 * map.memories.len() + 1;
    expected_macros(map).len() + functions + structs + 2 * regs + 2 * map.memories.len()
}

/// Compiles the self-test against the header in `dir` with `std` and runs
/// it: (passed, stdout).
fn compile_and_run_selftest(dir: &Path, std: &str) -> (bool, String) {
    let src = dir.join(selftest::FILE_NAME);
    let exe = dir.join(format!("selftest-{}", std.trim_start_matches("-std=")));
    let (ok, out, err) = run(Command::new("gcc")
        .args([std, "-Wall", "-Wextra", "-Werror", "-pedantic", "-I"])
        .arg(dir)
        .arg("-o")
        .arg(&exe)
        .arg(&src));
    assert!(ok && err.is_empty(), "{std}: gcc:\n{out}{err}");
    let (ok, out, _) = run(&mut Command::new(&exe));
    (ok, out)
}

fn write_pair(dir: &Path, map: &BusMap, header: &str) {
    fs::write(dir.join(c_header::FILE_NAME), header).unwrap();
    fs::write(dir.join(selftest::FILE_NAME), selftest::program(map)).unwrap();
}

#[test]
fn selftest_passes_in_c99_and_c11() {
    if require_tool("gcc").is_none() {
        return;
    }
    let mut configs = vec![Config::default()];
    configs.extend(other_configs());
    for (k, config) in configs.iter().enumerate() {
        let map = mcu_map(config);
        let want = expected_checks(&map);
        assert_eq!(selftest::checks(&map).len(), want, "config {k}: checks");
        if k == 0 {
            // 740 macros, 8 OFFSET(n), 89 struct offsets and sizes,
            // 2 x 140 register addresses and 2 RAM word addresses.
            assert_eq!(want, 740 + 8 + 89 + 280 + 2);
        }
        let dir = tempfile::tempdir().unwrap();
        write_pair(dir.path(), &map, &c_header::header(&map));
        for std in ["-std=c99", "-std=c11"] {
            let (ok, out) = compile_and_run_selftest(dir.path(), std);
            assert!(ok, "config {k} {std}: self-test failed:\n{out}");
            assert_eq!(out, format!("PASS {want} checks\n"), "config {k} {std}");
        }
    }
}

#[test]
fn selftest_fails_on_a_corrupted_header() {
    if require_tool("gcc").is_none() {
        return;
    }
    let map = default_map();
    let good = c_header::header(&map);
    // One mask wrong by one bit, then one struct's padding one word short.
    let mask = "#define MOTIONHDL_COUNTER_CH_CTRL__MODE_bm 0x0007u\n";
    let pad = "    uint32_t RESERVED0[2]; /* +0x018 */\n";
    for (what, from, to, failing) in [
        (
            "mask",
            mask,
            "#define MOTIONHDL_COUNTER_CH_CTRL__MODE_bm 0x000fu\n",
            "FAIL MOTIONHDL_COUNTER_CH_CTRL__MODE_bm: got 0xf, want 0x7",
        ),
        (
            "padding",
            pad,
            "    uint32_t RESERVED0[1]; /* +0x018 */\n",
            "FAIL sizeof(MOTIONHDL_COUNTER_CH_TypeDef): got 0x1c, want 0x20",
        ),
    ] {
        assert_eq!(
            good.matches(from).count(),
            1,
            "{what}: `{from}` not in the header once"
        );
        let bad = good.replace(from, to);
        let dir = tempfile::tempdir().unwrap();
        write_pair(dir.path(), &map, &bad);
        let (ok, out) = compile_and_run_selftest(dir.path(), "-std=c99");
        assert!(
            !ok,
            "{what}: the self-test passed a corrupted header:\n{out}"
        );
        assert!(out.contains(failing), "{what}: output:\n{out}");
        assert!(!out.contains("PASS"), "{what}");
        assert!(out.lines().last().unwrap().starts_with("FAILED "), "{what}");
    }
}
