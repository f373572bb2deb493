//! The MCU register map's exports (`motionhdl_regs.h` and its C self-test,
//! `motionhdl.svd`, `regmap.json`, `REGISTERS.md`, `motionhdl_regs.rs`),
//! each read back and compared with the one table,
//! `motionhdl_model::regmap::mcu_map`. Tests that need gcc, g++ or rustc
//! fail under CI when the tool is missing; elsewhere they are skipped.

use motionhdl::artifacts;
use motionhdl::regmap_export::{
    c_header, json, markdown, rust_module, selftest, svd, FSMC_NE1_BASE,
};
use motionhdl_hdl::banner;
use motionhdl_model::fsmc_bridge;
use motionhdl_model::regmap::{mcu_map, Access, Block, BusMap, Register, RegisterArray};
use motionhdl_model::{Config, IsaRam};
use motionhdl_testbench::harness::require_tool;
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

const P: &str = "MOTIONHDL";

fn default_map() -> BusMap {
    mcu_map(&Config::default())
}

/// The configurations the read-back tests cover besides the default: one
/// axis with the RAM outside the FPGA, and the largest bank.
fn other_configs() -> Vec<Config> {
    vec![
        Config::new(1, 8, 1_000_000)
            .unwrap()
            .with_isa_ram(IsaRam::External),
        Config::new(16, 32, 100_000_000).unwrap(),
    ]
}

fn run(cmd: &mut Command) -> (bool, String, String) {
    let o = cmd.output().expect("start tool");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).to_string(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

// ---------------------------------------------------------------------------
// The table, flattened: what every export must describe.

#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct FieldRec {
    name: String,
    lsb: u32,
    width: u32,
    access: &'static str,
    values: Vec<(String, u64)>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
struct RegRec {
    /// `BLOCK.REG`, `BLOCK.ARRAY[n].REG` or `MEMORY[n]`.
    path: String,
    bits: u32,
    access: &'static str,
    reset: u64,
    fields: Vec<FieldRec>,
}

fn tag(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "RO",
        Access::WriteOnly => "WO",
        Access::ReadWrite => "RW",
        Access::WriteOneToClear => "W1C",
    }
}

fn fields_of(r: &Register) -> Vec<FieldRec> {
    let mut v: Vec<FieldRec> = r
        .fields
        .iter()
        .map(|f| FieldRec {
            name: f.name.to_string(),
            lsb: f.lsb,
            width: f.width,
            access: tag(f.access),
            values: f
                .values
                .iter()
                .map(|e| (e.name.to_string(), u64::from(e.value)))
                .collect(),
        })
        .collect();
    v.sort();
    v
}

/// Every register (array registers once per element) and every memory
/// word, by byte offset from the window base; computed here from the table
/// alone.
fn table_set(map: &BusMap) -> BTreeMap<u64, RegRec> {
    let mut out = BTreeMap::new();
    let mut add = |offset: u32, rec: RegRec| {
        assert!(
            out.insert(u64::from(offset), rec).is_none(),
            "two registers at {offset:#x}"
        );
    };
    for b in &map.blocks {
        let base = b.base * 4;
        for r in &b.registers {
            add(
                base + r.offset * 4,
                RegRec {
                    path: format!("{}.{}", b.name, r.name),
                    bits: 32,
                    access: tag(r.access),
                    reset: u64::from(r.reset),
                    fields: fields_of(r),
                },
            );
        }
        for a in &b.arrays {
            for i in 0..a.count {
                for r in &a.registers {
                    add(
                        base + (a.offset + i * a.stride + r.offset) * 4,
                        RegRec {
                            path: format!("{}.{}[{i}].{}", b.name, a.name, r.name),
                            bits: 32,
                            access: tag(r.access),
                            reset: u64::from(r.reset),
                            fields: fields_of(r),
                        },
                    );
                }
            }
        }
    }
    for m in &map.memories {
        for i in 0..m.words {
            add(
                m.byte_offset + i * m.word_bits / 8,
                RegRec {
                    path: format!("{}[{i}]", m.name),
                    bits: m.word_bits,
                    access: "RW",
                    reset: 0,
                    fields: vec![],
                },
            );
        }
    }
    out
}

/// Registers (array registers once per element) and fields in the table.
fn table_counts(map: &BusMap) -> (usize, usize) {
    let mut regs = 0;
    let mut fields = 0;
    for b in &map.blocks {
        regs += b.registers.len();
        fields += b.registers.iter().map(|r| r.fields.len()).sum::<usize>();
        for a in &b.arrays {
            regs += a.count as usize * a.registers.len();
            fields += a.count as usize * a.registers.iter().map(|r| r.fields.len()).sum::<usize>();
        }
    }
    (regs, fields)
}

#[test]
fn default_table_has_the_registers_the_issue_describes() {
    let map = default_map();
    let set = table_set(&map);
    // ID: 9 registers; COUNTER: INFO, SNAPSHOT, PRESET + 4 x 5 CH
    // registers; PULSE: INFO, RUN + 4 x 10 AX registers; SHARED_RAM: 1024
    // words.
    assert_eq!(table_counts(&map).0, 9 + 3 + 4 * 5 + 2 + 4 * 10);
    assert_eq!(set.len(), 9 + 3 + 4 * 5 + 2 + 4 * 10 + 1024);
    assert_eq!(set[&0x840].path, "PULSE.AX[0].CTRL");
    assert_eq!(set[&0x420].path, "COUNTER.CH[0].CTRL");
    assert_eq!(set[&0x1000].path, "SHARED_RAM[0]");
    let external = mcu_map(&Config::default().with_isa_ram(IsaRam::External));
    assert!(external.memories.is_empty());
}

// ---------------------------------------------------------------------------
// Every file: banner, determinism, place in `motionhdl generate`.

#[test]
fn generate_writes_the_regmap_exports() {
    let config = Config::default();
    let all = artifacts::all(&config);
    for a in artifacts::regmap_exports(&config) {
        let in_all = all
            .iter()
            .find(|x| x.path == a.path)
            .unwrap_or_else(|| panic!("{} not in artifacts::all", a.path.display()));
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

// ---------------------------------------------------------------------------
// The C header.

/// Every `#define` of a header: (name, or name(params); replacement text).
fn defines(h: &str) -> Vec<(String, String)> {
    h.lines()
        .filter_map(|l| l.strip_prefix("#define "))
        .map(|rest| {
            let end = match rest.find('(') {
                Some(i) if !rest[..i].contains(' ') => rest.find(')').unwrap() + 1,
                _ => rest.find(' ').unwrap_or(rest.len()),
            };
            (rest[..end].to_string(), rest[end..].trim().to_string())
        })
        .collect()
}

fn c_number(s: &str) -> Option<u64> {
    let t = s.trim_end_matches(['u', 'U', 'l', 'L']);
    match t.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    }
}

fn expected_register_macros(
    v: &mut Vec<(String, u64)>,
    b: &Block,
    a: Option<&RegisterArray>,
    r: &Register,
) {
    let n = match a {
        None => format!("{P}_{}_{}", b.name, r.name),
        Some(a) => format!("{P}_{}_{}_{}", b.name, a.name, r.name),
    };
    v.push((format!("{n}_OFFSET"), u64::from(r.offset * 4)));
    v.push((format!("{n}_reset"), u64::from(r.reset)));
    for f in &r.fields {
        let fname = format!("{n}__{}", f.name);
        v.push((format!("{fname}_bm"), u64::from(f.mask())));
        v.push((format!("{fname}_bp"), u64::from(f.lsb)));
        v.push((format!("{fname}_bw"), u64::from(f.width)));
        v.push((format!("{fname}_reset"), u64::from(f.reset)));
        for e in &f.values {
            v.push((format!("{fname}__{}", e.name), u64::from(e.value)));
        }
    }
}

/// Every plain-number macro the header must define, from the table, named
/// as the issue asks.
fn expected_macros(map: &BusMap) -> BTreeMap<String, u64> {
    let id = map.block("ID");
    let mut v = vec![
        (format!("{P}_FSMC_NE1_BASE"), 0x6000_0000u64),
        (format!("{P}_WINDOW_SIZE"), u64::from(map.window_bytes())),
        (
            format!("{P}_MAP_HASH"),
            u64::from(id.register("MAP_HASH").reset),
        ),
        (
            format!("{P}_ID_MAGIC"),
            u64::from(id.register("MAGIC").reset),
        ),
    ];
    // The FSMC settings for the gateware's clock, from the bridge's budget.
    let clock_hz = u64::from(id.register("CLOCK_HZ").reset);
    let hclk_hz = fsmc_bridge::STM32F4_HCLK_HZ;
    if let Ok(b) = fsmc_bridge::stm32f4_budget_checked(clock_hz, hclk_hz) {
        let t = b.timing;
        v.push((format!("{P}_FSMC_HCLK_HZ"), hclk_hz));
        v.push((format!("{P}_FSMC_ADDSET"), u64::from(t.addset)));
        v.push((format!("{P}_FSMC_DATAST"), u64::from(t.datast)));
        v.push((format!("{P}_FSMC_BUSTURN"), u64::from(t.busturn)));
        v.push((format!("{P}_FSMC_BTR1"), u64::from(t.btr())));
    }
    for b in &map.blocks {
        v.push((format!("{P}_{}_BASE_OFFSET", b.name), u64::from(b.base * 4)));
        v.push((
            format!("{P}_{}_SIZE", b.name),
            u64::from((1u32 << b.address_bits) * 4),
        ));
        for r in &b.registers {
            expected_register_macros(&mut v, b, None, r);
        }
        for a in &b.arrays {
            v.push((
                format!("{P}_{}_{}_COUNT", b.name, a.name),
                u64::from(a.count),
            ));
            v.push((
                format!("{P}_{}_{}_STRIDE", b.name, a.name),
                u64::from(a.stride * 4),
            ));
            for r in &a.registers {
                expected_register_macros(&mut v, b, Some(a), r);
            }
        }
    }
    for m in &map.memories {
        v.push((
            format!("{P}_{}_BASE_OFFSET", m.name),
            u64::from(m.byte_offset),
        ));
        v.push((format!("{P}_{}_WORDS", m.name), u64::from(m.words)));
        v.push((format!("{P}_{}_WORD_BITS", m.name), u64::from(m.word_bits)));
        v.push((
            format!("{P}_{}_SIZE", m.name),
            u64::from(m.words * m.word_bits / 8),
        ));
    }
    let n = v.len();
    let m: BTreeMap<String, u64> = v.into_iter().collect();
    assert_eq!(m.len(), n, "expected macro names collide");
    m
}

fn check_header_numbers(map: &BusMap) -> usize {
    let h = c_header::header(map);
    let defs = defines(&h);
    // The CMSIS qualifiers are defined once for C and once for C++.
    let mut names: Vec<&String> = defs
        .iter()
        .map(|d| &d.0)
        .filter(|n| !n.starts_with("__"))
        .collect();
    names.sort();
    let n = names.len();
    names.dedup();
    assert_eq!(names.len(), n, "a macro is defined twice");
    let mut got = BTreeMap::new();
    let mut functions = BTreeSet::new();
    for (name, value) in &defs {
        if name.contains('(') {
            functions.insert(name.clone());
            continue;
        }
        if name == "MOTIONHDL_REGS_H" || name.starts_with("__") {
            continue;
        }
        let v =
            c_number(value).unwrap_or_else(|| panic!("{name}: `{value}` is not a plain number"));
        got.insert(name.clone(), v);
    }
    let want = expected_macros(map);
    assert_eq!(got, want, "numeric #defines against the table");
    let mut want_functions: BTreeSet<String> = map
        .blocks
        .iter()
        .flat_map(|b| {
            b.arrays
                .iter()
                .map(move |a| format!("{P}_{}_{}_OFFSET(n)", b.name, a.name))
        })
        .collect();
    want_functions.insert(format!("{P}(base)"));
    assert_eq!(functions, want_functions, "function-like macros");
    got.len()
}

#[test]
fn header_defines_every_number_of_the_table() {
    let map = default_map();
    let n = check_header_numbers(&map);
    // 4 globals and 5 FSMC settings; ID: 2 + 9 registers x 2 + 13 fields x 4 + 2 enum values;
    // COUNTER: 2 + 3 x 2 + 4 fields x 4, CH: 2 + 5 x 2 + 23 fields x 4 +
    // 5 enum values; PULSE: 2 + 2 x 2 + 3 fields x 4, AX: 2 + 10 x 2 +
    // 18 fields x 4 + 2 enum values; SHARED_RAM: 4.
    assert_eq!(
        n,
        4 + 5
            + (2 + 18 + 52 + 2)
            + (2 + 6 + 16)
            + (2 + 10 + 92 + 5)
            + (2 + 4 + 12)
            + (2 + 20 + 72 + 2)
            + 4
    );
    assert_eq!(n, 334);
    for c in other_configs() {
        check_header_numbers(&mcu_map(&c));
    }

    let h = c_header::header(&map);
    for want in [
        "#ifndef MOTIONHDL_REGS_H\n#define MOTIONHDL_REGS_H\n",
        "#include <stdint.h>",
        "#ifdef __cplusplus\nextern \"C\" {\n#endif",
        "#ifndef __I\n",
        "#define __I volatile const\n",
        "#ifndef __O\n#define __O volatile\n#endif",
        "#ifndef __IO\n#define __IO volatile\n#endif",
        "#define MOTIONHDL_FSMC_NE1_BASE 0x60000000u",
        "STM32F4 FSMC bank 1, region 1",
        "#define MOTIONHDL_COUNTER_CH_OFFSET(n) (0x0020u + (uint32_t)(n) * MOTIONHDL_COUNTER_CH_STRIDE)",
        "    __IO uint16_t SHARED_RAM[MOTIONHDL_SHARED_RAM_WORDS]; /* 0x1000 */",
        "} MOTIONHDL_COUNTER_CH_TypeDef;",
        "} MOTIONHDL_COUNTER_TypeDef;",
        "} MOTIONHDL_ID_TypeDef;",
        "} MOTIONHDL_TypeDef;",
        "    MOTIONHDL_COUNTER_CH_TypeDef CH[MOTIONHDL_COUNTER_CH_COUNT]; /* +0x020 */",
        "#define MOTIONHDL(base) ((MOTIONHDL_TypeDef *)(uintptr_t)(base))",
        "    __O  uint32_t SNAPSHOT;",
        "    __I  uint32_t COUNT;",
        "    __IO uint32_t CTRL;",
    ] {
        assert!(h.contains(want), "header lacks `{want}`");
    }
    assert!(h.ends_with("#endif /* MOTIONHDL_REGS_H */\n"));
    // Descriptions, side effects and access notes reach the comments.
    let counter = map.block("COUNTER");
    let cmd = counter.array("CH").register("CMD");
    assert!(h.contains("CH[n].CMD (CH[n] +0x04), write-only: "));
    let flat = h.replace("\n * ", " ");
    assert!(flat.contains(cmd.side_effects), "side effects of CMD");
    assert!(flat.contains(counter.register("SNAPSHOT").side_effects));
    assert!(flat.contains("Write-only: reads return 0."));
    assert!(flat.contains("Access registers only as 32-bit words, never as halfwords or bytes."));
    for r in &counter.array("CH").registers {
        assert!(flat.contains(r.description), "{}", r.name);
    }
}

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
            // 334 macros, 8 OFFSET(n), 42 struct offsets and sizes,
            // 2 x 74 register addresses and 2 RAM word addresses.
            assert_eq!(want, 334 + 8 + 42 + 148 + 2);
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
    let pad = "    uint32_t RESERVED0[3]; /* +0x014 */\n";
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
            "    uint32_t RESERVED0[2]; /* +0x014 */\n",
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

#[test]
fn header_compiles_as_cpp11() {
    if require_tool("g++").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    fs::write(
        dir.path().join(c_header::FILE_NAME),
        c_header::header(&default_map()),
    )
    .unwrap();
    let src = dir.path().join("t.cpp");
    fs::write(
        &src,
        "#include \"motionhdl_regs.h\"\n#include \"motionhdl_regs.h\"\n\
         static_assert(sizeof(MOTIONHDL_COUNTER_CH_TypeDef) == MOTIONHDL_COUNTER_CH_STRIDE, \"stride\");\n\
         int main() {\n\
         volatile MOTIONHDL_TypeDef *w = MOTIONHDL(MOTIONHDL_FSMC_NE1_BASE);\n\
         (void)w;\n\
         return 0;\n}\n",
    )
    .unwrap();
    for std in ["-std=c++11", "-std=c++17"] {
        let (ok, out, err) = run(Command::new("g++")
            .args([
                std,
                "-Wall",
                "-Wextra",
                "-Werror",
                "-pedantic",
                "-fsyntax-only",
                "-I",
            ])
            .arg(dir.path())
            .arg(&src));
        assert!(ok && err.is_empty(), "g++ {std}:\n{out}{err}");
    }
}

// ---------------------------------------------------------------------------
// SVD.

fn svd_access(
    a: Option<svd_rs::Access>,
    mwv: Option<svd_rs::ModifiedWriteValues>,
    what: &str,
) -> &'static str {
    use svd_rs::{Access as A, ModifiedWriteValues as M};
    match (a, mwv) {
        (Some(A::ReadOnly), None) => "RO",
        (Some(A::WriteOnly), None) => "WO",
        (Some(A::ReadWrite), None) => "RW",
        (Some(A::ReadWrite), Some(M::OneToClear)) => "W1C",
        other => panic!("{what}: unexpected access {other:?}"),
    }
}

fn svd_register(
    out: &mut BTreeMap<u64, RegRec>,
    window_base: u64,
    at: u64,
    path: String,
    r: &svd_rs::RegisterInfo,
) {
    let fields = r
        .fields
        .iter()
        .flatten()
        .map(|f| {
            assert!(f.is_single(), "{path}.{}: field array", f.name);
            let values = f
                .enumerated_values
                .iter()
                .flat_map(|ev| ev.values.iter())
                .map(|v| (v.name.clone(), v.value.unwrap()))
                .collect();
            FieldRec {
                name: f.name.clone(),
                lsb: f.bit_range.offset,
                width: f.bit_range.width,
                access: svd_access(
                    f.access,
                    f.modified_write_values,
                    &format!("{path}.{}", f.name),
                ),
                values,
            }
        })
        .collect::<Vec<_>>();
    let mut fields = fields;
    fields.sort();
    assert_eq!(
        r.properties.reset_mask,
        Some(if r.properties.size == Some(32) {
            0xffff_ffff
        } else {
            0
        }),
        "{path}"
    );
    let rec = RegRec {
        path: path.clone(),
        bits: r.properties.size.expect("size"),
        access: svd_access(r.properties.access, r.modified_write_values, &path),
        reset: r.properties.reset_value.expect("resetValue"),
        fields,
    };
    assert!(
        out.insert(at - window_base, rec).is_none(),
        "{path}: two registers at {at:#x}"
    );
}

/// Every register of an SVD device, dim arrays and clusters expanded, by
/// byte offset from `window_base`; names as in `table_set`.
fn svd_set(dev: &svd_rs::Device, window_base: u64) -> BTreeMap<u64, RegRec> {
    use svd_rs::{MaybeArray, RegisterCluster};
    let mut out = BTreeMap::new();
    for p in &dev.peripherals {
        assert!(p.is_single(), "{}: peripheral array", p.name);
        for rc in p.registers.iter().flatten() {
            match rc {
                RegisterCluster::Register(MaybeArray::Single(r)) => {
                    let path = format!("{}.{}", p.name, r.name);
                    svd_register(
                        &mut out,
                        window_base,
                        p.base_address + u64::from(r.address_offset),
                        path,
                        r,
                    );
                }
                RegisterCluster::Register(MaybeArray::Array(r, dim)) => {
                    // A memory window: WORD[%s] -> MEMORY[n].
                    assert_eq!(r.name, "WORD[%s]");
                    for (i, idx) in dim.indexes().enumerate() {
                        let at = p.base_address
                            + u64::from(r.address_offset)
                            + i as u64 * u64::from(dim.dim_increment);
                        svd_register(&mut out, window_base, at, format!("{}[{idx}]", p.name), r);
                    }
                }
                RegisterCluster::Cluster(MaybeArray::Array(c, dim)) => {
                    let name = c.name.strip_suffix("[%s]").expect("cluster array name");
                    assert_eq!(dim.indexes().count(), dim.dim as usize);
                    for (i, idx) in dim.indexes().enumerate() {
                        let base = p.base_address
                            + u64::from(c.address_offset)
                            + i as u64 * u64::from(dim.dim_increment);
                        for child in &c.children {
                            match child {
                                RegisterCluster::Register(MaybeArray::Single(r)) => {
                                    let path = format!("{}.{name}[{idx}].{}", p.name, r.name);
                                    svd_register(
                                        &mut out,
                                        window_base,
                                        base + u64::from(r.address_offset),
                                        path,
                                        r,
                                    );
                                }
                                other => panic!("unexpected in a cluster: {other:?}"),
                            }
                        }
                    }
                }
                RegisterCluster::Cluster(c) => panic!("single cluster {}", c.name),
            }
        }
    }
    out
}

fn check_svd(map: &BusMap) -> (usize, usize) {
    let text = svd::svd(map);
    let config = svd_parser::Config::default().validate_level(svd_rs::ValidateLevel::Strict);
    let dev = svd_parser::parse_with_config(&text, &config).expect("the SVD parses");
    assert_eq!(dev.name, "MOTIONHDL");
    assert_eq!(dev.version, motionhdl_hdl::VERSION);
    assert_eq!(dev.schema_version, "1.3");
    assert_eq!(dev.address_unit_bits, 8);
    assert_eq!(dev.width, 32);
    assert_eq!(dev.default_register_properties.size, Some(32));
    let names: Vec<&str> = dev.peripherals.iter().map(|p| p.name.as_str()).collect();
    let mut want: Vec<&str> = map.blocks.iter().map(|b| b.name).collect();
    want.extend(map.memories.iter().map(|m| m.name));
    assert_eq!(names, want, "peripherals");
    for p in &dev.peripherals {
        let offset = map
            .blocks
            .iter()
            .find(|b| b.name == p.name)
            .map(|b| b.base * 4)
            .or_else(|| {
                map.memories
                    .iter()
                    .find(|m| m.name == p.name)
                    .map(|m| m.byte_offset)
            })
            .unwrap();
        assert_eq!(
            p.base_address,
            u64::from(FSMC_NE1_BASE + offset),
            "{}",
            p.name
        );
    }
    let got = svd_set(&dev, u64::from(FSMC_NE1_BASE));
    let want = table_set(map);
    assert_eq!(got.len(), want.len(), "registers + memory words");
    for (at, w) in &want {
        assert_eq!(got.get(at), Some(w), "at {at:#x}");
    }
    assert_eq!(got, want);
    let fields: usize = got.values().map(|r| r.fields.len()).sum();
    assert_eq!(fields, table_counts(map).1);
    // The CH and AX arrays are one cluster each with dim = axes.
    assert_eq!(text.matches("<cluster>").count(), 2);
    // Descriptions, escaped and parsed back.
    let id = dev.get_peripheral("ID").unwrap();
    let magic = id.get_register("MAGIC").unwrap();
    assert_eq!(
        magic.description.as_deref(),
        Some(map.block("ID").register("MAGIC").description)
    );
    (got.len(), fields)
}

#[test]
fn svd_parses_back_to_the_table() {
    let (regs, fields) = check_svd(&default_map());
    // 74 registers and 1024 RAM words; ID 13 fields, COUNTER 4 + 4 x 23,
    // PULSE 3 + 4 x 18.
    assert_eq!(regs, 74 + 1024);
    assert_eq!(fields, 13 + 4 + 4 * 23 + 3 + 4 * 18);
    for c in other_configs() {
        check_svd(&mcu_map(&c));
    }
    let text = svd::svd(&default_map());
    for want in [
        "<dim>4</dim>",
        "<dimIncrement>0x20</dimIncrement>",
        "<dimIndex>0-3</dimIndex>",
        "<name>CH[%s]</name>",
        "<name>AX[%s]</name>",
        "<dimIncrement>0x40</dimIncrement>",
        "<baseAddress>0x60000400</baseAddress>",
        "<baseAddress>0x60001000</baseAddress>",
        "<dim>1024</dim>",
        "<size>16</size>",
        "<addressUnitBits>8</addressUnitBits>",
    ] {
        assert!(text.contains(want), "SVD lacks `{want}`");
    }
    assert_eq!(
        svd::escape("a<b & \"c\">'d'"),
        "a&lt;b &amp; &quot;c&quot;&gt;&apos;d&apos;"
    );
}

#[test]
fn svd_marks_write_one_to_clear() {
    // No MCU register is W1C today; the ISA block's STATUS is, so its SVD
    // rendering is checked through a map holding that block.
    let mut map = default_map();
    let mut isa = motionhdl_model::regmap::isa_bridge();
    isa.base = 0x300;
    map.blocks.push(isa);
    let text = svd::svd(&map);
    assert_eq!(
        text.matches("<modifiedWriteValues>oneToClear</modifiedWriteValues>")
            .count(),
        2
    );
    check_svd(&map);
    check_header_numbers(&map);
    check_json(&map);
}

// ---------------------------------------------------------------------------
// JSON.

fn json_access(s: &str) -> &'static str {
    match s {
        "read-only" => "RO",
        "write-only" => "WO",
        "read-write" => "RW",
        "write-1-to-clear" => "W1C",
        other => panic!("access {other}"),
    }
}

fn u(v: &serde_json::Value) -> u64 {
    v.as_u64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn s(v: &serde_json::Value) -> &str {
    v.as_str().unwrap_or_else(|| panic!("not a string: {v}"))
}

fn json_fields(r: &serde_json::Value, table: &Register) -> Vec<FieldRec> {
    let mut v: Vec<FieldRec> = r["fields"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let tf = table.field(s(&f["name"]));
            assert_eq!(u(&f["mask"]), u64::from(tf.mask()));
            assert_eq!(u(&f["reset"]), u64::from(tf.reset));
            assert_eq!(s(&f["description"]), tf.description);
            FieldRec {
                name: s(&f["name"]).to_string(),
                lsb: u(&f["lsb"]) as u32,
                width: u(&f["width"]) as u32,
                access: json_access(s(&f["access"])),
                values: f["values"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|e| (s(&e["name"]).to_string(), u(&e["value"])))
                    .collect(),
            }
        })
        .collect();
    v.sort();
    v
}

fn json_reg(r: &serde_json::Value, table: &Register, path: String) -> RegRec {
    assert_eq!(s(&r["description"]), table.description, "{path}");
    assert_eq!(s(&r["side_effects"]), table.side_effects, "{path}");
    RegRec {
        path,
        bits: 32,
        access: json_access(s(&r["access"])),
        reset: u(&r["reset"]),
        fields: json_fields(r, table),
    }
}

fn check_json(map: &BusMap) -> usize {
    let text = json::json(map);
    let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(s(&v["generated_by"]), banner());
    assert_eq!(s(&v["name"]), map.name);
    assert_eq!(s(&v["version"]), motionhdl_hdl::VERSION);
    assert_eq!(
        u(&v["map_hash"]),
        u64::from(map.block("ID").register("MAP_HASH").reset)
    );
    assert_eq!(u(&v["bus"]["window_bytes"]), u64::from(map.window_bytes()));
    assert_eq!(u(&v["bus"]["default_base_address"]), 0x6000_0000);
    assert_eq!(u(&v["bus"]["data_bits"]), 16);
    let mut got = BTreeMap::new();
    let mut add = |at: u64, rec: RegRec| assert!(got.insert(at, rec).is_none(), "two at {at:#x}");
    for (jb, b) in v["blocks"].as_array().unwrap().iter().zip(&map.blocks) {
        assert_eq!(s(&jb["name"]), b.name);
        assert_eq!(s(&jb["description"]), b.description);
        assert_eq!(u(&jb["byte_offset"]), u64::from(b.base * 4));
        assert_eq!(
            u(&jb["size_bytes"]),
            u64::from((1u32 << b.address_bits) * 4)
        );
        for jr in jb["registers"].as_array().unwrap() {
            let r = b.register(s(&jr["name"]));
            add(
                u(&jr["byte_offset"]),
                json_reg(jr, r, format!("{}.{}", b.name, r.name)),
            );
        }
        for (ja, a) in jb["arrays"].as_array().unwrap().iter().zip(&b.arrays) {
            assert_eq!(s(&ja["name"]), a.name);
            assert_eq!(u(&ja["count"]), u64::from(a.count));
            assert_eq!(u(&ja["stride_bytes"]), u64::from(a.stride * 4));
            assert_eq!(u(&ja["byte_offset"]), u64::from((b.base + a.offset) * 4));
            for jr in ja["registers"].as_array().unwrap() {
                let r = a.register(s(&jr["name"]));
                assert_eq!(u(&jr["element_offset"]), u64::from(r.offset * 4));
                let offsets = jr["byte_offsets"].as_array().unwrap();
                assert_eq!(offsets.len(), a.count as usize);
                for (i, at) in offsets.iter().enumerate() {
                    let path = format!("{}.{}[{i}].{}", b.name, a.name, r.name);
                    add(u(at), json_reg(jr, r, path));
                }
            }
        }
    }
    assert_eq!(v["blocks"].as_array().unwrap().len(), map.blocks.len());
    let mems = v["memories"].as_array().unwrap();
    assert_eq!(mems.len(), map.memories.len());
    for (jm, m) in mems.iter().zip(&map.memories) {
        assert_eq!(s(&jm["name"]), m.name);
        assert_eq!(s(&jm["description"]), m.description);
        assert_eq!(u(&jm["word_bits"]), u64::from(m.word_bits));
        assert_eq!(u(&jm["size_bytes"]), u64::from(m.words * m.word_bits / 8));
        for i in 0..u(&jm["words"]) {
            add(
                u(&jm["byte_offset"]) + i * u(&jm["word_bits"]) / 8,
                RegRec {
                    path: format!("{}[{i}]", s(&jm["name"])),
                    bits: u(&jm["word_bits"]) as u32,
                    access: "RW",
                    reset: 0,
                    fields: vec![],
                },
            );
        }
    }
    let want = table_set(map);
    assert_eq!(got.len(), want.len());
    assert_eq!(got, want);
    got.len()
}

#[test]
fn json_parses_back_to_the_table() {
    assert_eq!(check_json(&default_map()), 74 + 1024);
    for c in other_configs() {
        check_json(&mcu_map(&c));
    }
}

// ---------------------------------------------------------------------------
// Markdown.

#[test]
fn markdown_documents_every_register_field_and_the_ram() {
    for config in std::iter::once(Config::default()).chain(other_configs()) {
        let map = mcu_map(&config);
        let md = markdown::markdown(&map);
        let mut rows = 0;
        for b in &map.blocks {
            assert!(md.contains(&format!("\n## {}\n", b.name)), "{}", b.name);
            for r in &b.registers {
                let row = format!(
                    "| `{:#06x}` | [{}](#{}) | {} | `0x{:08X}` |",
                    b.base * 4 + r.offset * 4,
                    r.name,
                    format!("{}-{}", b.name, r.name).to_lowercase(),
                    tag(r.access),
                    r.reset
                );
                assert!(md.contains(&row), "no row `{row}`");
                assert!(md.contains(&format!("#### {}.{}\n", b.name, r.name)));
                rows += 1;
            }
            for a in &b.arrays {
                for r in &a.registers {
                    let row = format!(
                        "| `{:#06x}` + n × `{:#x}` ({}[n], n = 0..{}) | [{}](#",
                        (b.base + a.offset + r.offset) * 4,
                        a.stride * 4,
                        a.name,
                        a.count - 1,
                        r.name
                    );
                    assert!(md.contains(&row), "no row `{row}`");
                    assert!(md.contains(&format!("#### {}.{}[n].{}\n", b.name, a.name, r.name)));
                    rows += 1;
                }
            }
            for r in b
                .registers
                .iter()
                .chain(b.arrays.iter().flat_map(|a| a.registers.iter()))
            {
                for f in &r.fields {
                    let bits = if f.width == 1 {
                        f.lsb.to_string()
                    } else {
                        format!("{}:{}", f.lsb + f.width - 1, f.lsb)
                    };
                    let row = format!(
                        "| {bits} | {} | {} | `{:#x}` | {}",
                        f.name,
                        tag(f.access),
                        f.reset,
                        f.description
                    );
                    assert!(md.contains(&row), "no row `{row}`");
                    for e in &f.values {
                        assert!(md.contains(&format!("`{}` = {}: ", e.name, e.value)));
                    }
                }
            }
        }
        assert_eq!(
            rows,
            map.blocks
                .iter()
                .map(|b| b.registers.len()
                    + b.arrays.iter().map(|a| a.registers.len()).sum::<usize>())
                .sum::<usize>()
        );
        assert!(md.contains("**32-bit access only.**"));
        for m in &map.memories {
            assert!(md.contains(&format!(
                "{} words of {} bits, word n at byte offset `{:#06x}`",
                m.words, m.word_bits, m.byte_offset
            )));
        }
        if map.memories.is_empty() {
            assert!(md.contains("there is no RAM window on this bus"));
        }
    }
}

// ---------------------------------------------------------------------------
// The Rust module.

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
    assert_eq!(regs::counter::ch::COUNT as u32, ch.count);
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
            v.push((format!("{ap}::COUNT"), u64::from(a.count)));
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

        // A no_std library holding the module.
        let lib = dir.path().join("lib.rs");
        fs::write(&lib, "#![no_std]\n#![deny(missing_docs)]\n//! Firmware crate.\n\n/// Registers.\npub mod motionhdl_regs;\n").unwrap();
        let (ok, out, err) = run(Command::new(&rustc)
            .args([
                "--crate-type",
                "lib",
                "--edition",
                "2021",
                "-D",
                "warnings",
                "--crate-name",
                "fw",
            ])
            .arg("--out-dir")
            .arg(dir.path())
            .arg(&lib));
        assert!(
            ok && err.is_empty(),
            "config {k}: rustc no_std lib:\n{out}{err}"
        );

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
            // 4 globals; ID 2 + 9 x 2 + 13 x 4 + 2; COUNTER 2 + 3 x 2 + 4 x 4,
            // CH 3 + 4 + 5 x 2 + 23 x 4 + 5; PULSE 2 + 2 x 2 + 3 x 4, AX 3 +
            // 4 + 10 x 2 + 18 x 4 + 2; SHARED_RAM 4.
            assert_eq!(expected.len(), 4 + 74 + 24 + 114 + 18 + 101 + 4);
        }
    }
}
