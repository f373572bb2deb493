//! The MCU register map's exports as a set (`motionhdl_regs.h` and its C
//! self-test, `motionhdl.svd`, `regmap.json`, `REGISTERS.md`,
//! `motionhdl_regs.rs`): the table they are read from, and every file's
//! banner, determinism and place in `motionhdl generate`. Each format is
//! read back against the table in its own `tests/regmap_*.rs`.

mod common;

use common::regmap::{default_map, table_counts, table_set};
use motionhdl::artifacts;
use motionhdl_hdl::banner;
use motionhdl_model::regmap::mcu_map;
use motionhdl_model::{Config, IsaRam};
use std::path::PathBuf;

#[test]
fn default_table_has_the_registers_the_issue_describes() {
    let map = default_map();
    let set = table_set(&map);
    // ID: 10 registers; COUNTER: INFO, SNAPSHOT, PRESET + 4 x 6 CH
    // registers; PULSE: INFO, RUN + 4 x 16 AX registers; SAFETY: 37;
    // SHARED_RAM: 1024 words.
    assert_eq!(table_counts(&map).0, 10 + 3 + 4 * 6 + 2 + 4 * 16 + 37);
    assert_eq!(set.len(), 10 + 3 + 4 * 6 + 2 + 4 * 16 + 37 + 1024);
    assert_eq!(set[&0x208].path, "SAFETY.CLEAR");
    assert_eq!(set[&0x840].path, "PULSE.AX[0].CTRL");
    assert_eq!(set[&0x420].path, "COUNTER.CH[0].CTRL");
    assert_eq!(set[&0x1000].path, "SHARED_RAM[0]");
    let external = mcu_map(&Config::default().with_isa_ram(IsaRam::External));
    assert!(external.memories.is_empty());
}

#[test]
fn generate_writes_the_regmap_exports() {
    let config = Config::default();
    let all = artifacts::without_traces(&config);
    for a in artifacts::regmap_exports(&config) {
        let in_all = all
            .iter()
            .find(|x| x.path == a.path)
            .unwrap_or_else(|| panic!("{} not in the generated files", a.path.display()));
        assert!(in_all.contents == a.contents, "{}", a.path.display());
    }
}

#[test]
fn exports_are_bannered_and_deterministic() {
    let config = Config::default();
    let mine = artifacts::regmap_exports(&config);
    let want_paths: Vec<PathBuf> = [
        "include/motionhdl_regs.h",
        "test/motionhdl_regs_selftest.c",
        "motionhdl.svd",
        "regmap.json",
        "regmap.schema.json",
        "REGISTERS.md",
        "rust/motionhdl_regs.rs",
    ]
    .iter()
    .map(PathBuf::from)
    .collect();
    let paths: Vec<PathBuf> = mine.iter().map(|a| a.path.clone()).collect();
    assert_eq!(paths, want_paths);
    let again = artifacts::regmap_exports(&config);
    for (a, b) in mine.iter().zip(&again) {
        assert!(
            a.contents == b.contents,
            "{}: not deterministic",
            a.path.display()
        );
        let text = std::str::from_utf8(&a.contents).unwrap();
        let first = text.lines().next().unwrap();
        let ext = a.path.extension().unwrap().to_str().unwrap();
        let want = match ext {
            "h" | "c" => format!("/* {} */", banner()),
            "svd" | "md" => format!("<!-- {} -->", banner()),
            "rs" => format!("// {}", banner()),
            "json" if a.path.ends_with("regmap.schema.json") => {
                format!("{{\"$comment\": \"{}\",", banner())
            }
            "json" => format!("{{\"generated_by\": \"{}\",", banner()),
            _ => unreachable!(),
        };
        assert_eq!(first, want, "{}: first line", a.path.display());
        assert!(
            text.ends_with('\n') && !text.ends_with("\n\n"),
            "{}",
            a.path.display()
        );
        for (i, l) in text.lines().enumerate() {
            assert!(
                !l.ends_with(' '),
                "{}:{}: trailing space",
                a.path.display(),
                i + 1
            );
            if ext != "md" && ext != "json" && ext != "svd" {
                assert!(
                    l.chars().count() <= 100,
                    "{}:{}: too long",
                    a.path.display(),
                    i + 1
                );
            }
            if i > 0 && (ext == "h" || ext == "c" || ext == "rs") {
                assert!(l.is_ascii(), "{}:{}: not ASCII", a.path.display(), i + 1);
            }
        }
        // No dates: nothing like YYYY-MM-DD.
        let b = text.as_bytes();
        let date = b.windows(10).any(|w| {
            w.iter().enumerate().all(|(i, c)| {
                if i == 4 || i == 7 {
                    *c == b'-'
                } else {
                    c.is_ascii_digit()
                }
            })
        });
        assert!(
            !date && !text.contains("$date"),
            "{}: a date",
            a.path.display()
        );
    }
}
