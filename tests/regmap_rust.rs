//! `motionhdl_regs.rs`, the `no_std` Rust module of the MCU register map:
//! the committed copy included here and compared with the table, and each
//! configuration's module built by rustc as a `no_std` library and checked
//! constant by constant. A test that needs rustc fails under CI when it is
//! missing; elsewhere it is skipped.

mod common;

use common::regmap::{default_map, other_configs};
use common::run;
use motionhdl::regmap_export::{rust_module, FSMC_NE1_BASE};
use motionhdl_model::regmap::{mcu_map, BusMap, Register};
use motionhdl_model::Config;
use motionhdl_testbench::harness::require_tool;
use std::fs;
use std::path::Path;
use std::process::Command;

#[allow(dead_code)]
mod regs {
    include!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/generated/rust/motionhdl_regs.rs"
    ));
}

#[test]
fn rust_module_included_matches_the_table() {
    let map = default_map();
    // The included file is the committed one; it must be this generator's.
    let committed = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/rust/motionhdl_regs.rs"),
    )
    .unwrap();
    assert_eq!(committed, rust_module::module(&map), "generated/ is stale");

    let id = map.block("ID");
    let counter = map.block("COUNTER");
    let ch = counter.array("CH");
    let ram = &map.memories[0];
    assert_eq!(regs::FSMC_NE1_BASE, 0x6000_0000);
    assert_eq!(regs::WINDOW_SIZE as u32, map.window_bytes());
    assert_eq!(regs::MAP_HASH, id.register("MAP_HASH").reset);
    assert_eq!(regs::ID_MAGIC, id.register("MAGIC").reset);
    assert_eq!(regs::id::BASE_OFFSET as u32, id.base * 4);
    assert_eq!(regs::counter::BASE_OFFSET as u32, counter.base * 4);
    assert_eq!(regs::counter::SIZE as u32, (1 << counter.address_bits) * 4);
    assert_eq!(regs::counter::ch::LEN as u32, ch.count);
    assert_eq!(regs::counter::ch::STRIDE as u32, ch.stride * 4);
    for i in 0..ch.count {
        assert_eq!(
            regs::counter::ch::offset(i as usize) as u32,
            (ch.offset + i * ch.stride) * 4
        );
        assert_eq!(
            (regs::counter::BASE_OFFSET
                + regs::counter::ch::offset(i as usize)
                + regs::counter::ch::status::OFFSET) as u32,
            (counter.base + ch.address(i, "STATUS")) * 4
        );
    }
    let ctrl = ch.register("CTRL");
    let mode = ctrl.field("MODE");
    assert_eq!(regs::counter::ch::ctrl::OFFSET as u32, ctrl.offset * 4);
    assert_eq!(regs::counter::ch::ctrl::RESET, ctrl.reset);
    assert_eq!(regs::counter::ch::ctrl::mode::MASK, mode.mask());
    assert_eq!(regs::counter::ch::ctrl::mode::POS, mode.lsb);
    assert_eq!(regs::counter::ch::ctrl::mode::WIDTH, mode.width);
    assert_eq!(regs::counter::ch::ctrl::mode::RESET, mode.reset);
    let values = [
        ("X4", regs::counter::ch::ctrl::mode::X4),
        ("X2", regs::counter::ch::ctrl::mode::X2),
        ("X1", regs::counter::ch::ctrl::mode::X1),
        ("PULSE_DIR", regs::counter::ch::ctrl::mode::PULSE_DIR),
        ("CW_CCW", regs::counter::ch::ctrl::mode::CW_CCW),
    ];
    assert_eq!(values.len(), mode.values.len());
    for (name, v) in values {
        assert_eq!(
            mode.values.iter().find(|e| e.name == name).unwrap().value,
            v
        );
    }
    let err_count = ch.register("STATUS").field("ERR_COUNT");
    assert_eq!(regs::counter::ch::status::err_count::MASK, err_count.mask());
    assert_eq!(regs::counter::info::RESET, counter.register("INFO").reset);
    assert_eq!(
        regs::counter::snapshot::OFFSET as u32,
        counter.register("SNAPSHOT").offset * 4
    );
    assert_eq!(regs::id::config::isa_ram::EXTERNAL, 1);
    assert_eq!(
        regs::id::map_hash::OFFSET as u32,
        id.register("MAP_HASH").offset * 4
    );
    assert_eq!(regs::shared_ram::BASE_OFFSET as u32, ram.byte_offset);
    assert_eq!(regs::shared_ram::WORDS as u32, ram.words);
    assert_eq!(regs::shared_ram::WORD_BITS, ram.word_bits);

    // The volatile helpers, on plain memory.
    let mut words = [0u32; 4];
    let base = words.as_mut_ptr() as usize;
    unsafe {
        regs::write32(base, 8, 0x1234_5678);
        assert_eq!(regs::read32(base, 8), 0x1234_5678);
        regs::write16(base, 2, 0xbeef);
        assert_eq!(regs::read16(base, 2), 0xbeef);
    }
    assert_eq!(words[2], 0x1234_5678);
}

/// Every constant of the Rust module as (path, value), from the table.
fn rust_expected(map: &BusMap) -> Vec<(String, u64)> {
    let m = rust_module::module_name;
    let id = map.block("ID");
    let mut v = vec![
        ("FSMC_NE1_BASE".to_string(), u64::from(FSMC_NE1_BASE)),
        ("WINDOW_SIZE".to_string(), u64::from(map.window_bytes())),
        (
            "MAP_HASH".to_string(),
            u64::from(id.register("MAP_HASH").reset),
        ),
        (
            "ID_MAGIC".to_string(),
            u64::from(id.register("MAGIC").reset),
        ),
    ];
    let reg = |v: &mut Vec<(String, u64)>, p: &str, r: &Register| {
        let p = format!("{p}::{}", m(r.name));
        v.push((format!("{p}::OFFSET"), u64::from(r.offset * 4)));
        v.push((format!("{p}::RESET"), u64::from(r.reset)));
        for f in &r.fields {
            let fp = format!("{p}::{}", m(f.name));
            v.push((format!("{fp}::MASK"), u64::from(f.mask())));
            v.push((format!("{fp}::POS"), u64::from(f.lsb)));
            v.push((format!("{fp}::WIDTH"), u64::from(f.width)));
            v.push((format!("{fp}::RESET"), u64::from(f.reset)));
            for e in &f.values {
                v.push((format!("{fp}::{}", e.name), u64::from(e.value)));
            }
        }
    };
    for b in &map.blocks {
        let bp = m(b.name);
        v.push((format!("{bp}::BASE_OFFSET"), u64::from(b.base * 4)));
        v.push((
            format!("{bp}::SIZE"),
            u64::from((1u32 << b.address_bits) * 4),
        ));
        for r in &b.registers {
            reg(&mut v, &bp, r);
        }
        for a in &b.arrays {
            let ap = format!("{bp}::{}", m(a.name));
            v.push((format!("{ap}::LEN"), u64::from(a.count)));
            v.push((format!("{ap}::STRIDE"), u64::from(a.stride * 4)));
            v.push((format!("{ap}::OFFSET"), u64::from(a.offset * 4)));
            for i in 0..a.count {
                v.push((
                    format!("{ap}::offset({i})"),
                    u64::from((a.offset + i * a.stride) * 4),
                ));
            }
            for r in &a.registers {
                reg(&mut v, &ap, r);
            }
        }
    }
    for mem in &map.memories {
        let mp = m(mem.name);
        v.push((format!("{mp}::BASE_OFFSET"), u64::from(mem.byte_offset)));
        v.push((format!("{mp}::WORDS"), u64::from(mem.words)));
        v.push((format!("{mp}::WORD_BITS"), u64::from(mem.word_bits)));
        v.push((
            format!("{mp}::SIZE"),
            u64::from(mem.words * mem.word_bits / 8),
        ));
    }
    v
}

fn rustc() -> Option<String> {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string());
    if Path::new(&rustc).is_absolute() {
        return Some(rustc);
    }
    require_tool(&rustc).map(|p| p.to_string_lossy().to_string())
}

#[test]
fn rust_module_builds_no_std_and_every_constant_is_the_tables() {
    let Some(rustc) = rustc() else {
        return;
    };
    let mut configs = vec![Config::default()];
    configs.extend(other_configs());
    for (k, config) in configs.iter().enumerate() {
        let map = mcu_map(config);
        let module = rust_module::module(&map);
        assert!(!module.contains("std::") && !module.contains("extern crate"));
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join(rust_module::FILE_NAME), &module).unwrap();

        // A no_std library holding the module, in the edition a firmware
        // crate has (2024 is what `cargo new` picks).
        let lib = dir.path().join("lib.rs");
        fs::write(&lib, "#![no_std]\n#![deny(missing_docs)]\n//! Firmware crate.\n\n/// Registers.\npub mod motionhdl_regs;\n").unwrap();
        for edition in ["2021", "2024"] {
            let (ok, out, err) = run(Command::new(&rustc)
                .args(["--crate-type", "lib", "--edition", edition])
                .args(["-D", "warnings", "--crate-name", "fw"])
                .arg("--out-dir")
                .arg(dir.path())
                .arg(&lib));
            assert!(
                ok && err.is_empty(),
                "config {k}: rustc --edition {edition} no_std lib:\n{out}{err}"
            );
        }

        // A program comparing every constant with the table's value.
        let expected = rust_expected(&map);
        let mut main = String::from(
            "#[allow(dead_code)]\nmod motionhdl_regs;\nuse motionhdl_regs as r;\n\
             fn main() {\n    let mut n = 0u32;\n    let mut bad = 0u32;\n",
        );
        for (path, value) in &expected {
            main.push_str(&format!(
                "    if r::{path} as u64 == {value}u64 {{ n += 1; }} else {{ bad += 1; println!(\"FAIL {path}\"); }}\n"
            ));
        }
        main.push_str("    println!(\"PASS {n} FAIL {bad}\");\n    std::process::exit(if bad == 0 { 0 } else { 1 });\n}\n");
        let src = dir.path().join("main.rs");
        fs::write(&src, main).unwrap();
        let exe = dir.path().join("check");
        let (ok, out, err) = run(Command::new(&rustc)
            .args(["--edition", "2021", "-D", "warnings", "-o"])
            .arg(&exe)
            .arg(&src));
        assert!(
            ok && err.is_empty(),
            "config {k}: rustc check program:\n{out}{err}"
        );
        let (ok, out, _) = run(&mut Command::new(&exe));
        assert!(ok, "config {k}: constants differ:\n{out}");
        assert_eq!(out, format!("PASS {} FAIL 0\n", expected.len()));
        if k == 0 {
            // 4 globals; ID 2 + 10 x 2 + 14 x 4 + 2; COUNTER 2 + 3 x 2 + 8 x 4,
            // CH 3 + 4 + 6 x 2 + 24 x 4 + 5; PULSE 2 + 2 x 2 + 3 x 4, AX 3 +
            // 4 + 16 x 2 + 26 x 4 + 2; SAFETY 2 + 37 x 2 + 64 x 4 + 2;
            // SHARED_RAM 4.
            assert_eq!(expected.len(), 4 + 80 + 40 + 120 + 18 + 145 + 334 + 4);
        }
    }
}
