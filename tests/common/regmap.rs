//! The MCU register map's table, `motionhdl_model::regmap::mcu_map`,
//! flattened into what every export must describe, and the read-backs of
//! the C header and the JSON that more than one test file runs.

use super::{c_number, defines};
use motionhdl::regmap_export::{c_header, json};
use motionhdl_hdl::banner;
use motionhdl_model::fsmc_bridge;
use motionhdl_model::regmap::{mcu_map, Access, Block, BusMap, Register, RegisterArray};
use motionhdl_model::{Config, CounterFeatures, IsaRam};
use std::collections::{BTreeMap, BTreeSet};

pub const P: &str = "MOTIONHDL";

pub fn default_map() -> BusMap {
    mcu_map(&Config::default())
}

/// The configurations the read-back tests cover besides the default: one
/// axis with the RAM outside the FPGA, and the largest bank.
pub fn other_configs() -> Vec<Config> {
    vec![
        Config::new(1, 8, 1_000_000)
            .unwrap()
            .with_isa_ram(IsaRam::External),
        Config::new(16, 32, 100_000_000).unwrap(),
        // The DSP seed card's counter features: no filter, index or error
        // detection (the exports drop their fields and the INDEX register).
        Config::default().with_counter_features(CounterFeatures::from_bits(8)),
        // The servo card: SERVO at byte 0x40 (CH[4] of CODE and OUTPUT).
        Config::default().with_servo_dac(true),
    ]
}

// ---------------------------------------------------------------------------
// The table, flattened.

#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct FieldRec {
    pub name: String,
    pub lsb: u32,
    pub width: u32,
    pub access: &'static str,
    pub values: Vec<(String, u64)>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegRec {
    /// `BLOCK.REG`, `BLOCK.ARRAY[n].REG` or `MEMORY[n]`.
    pub path: String,
    pub bits: u32,
    pub access: &'static str,
    pub reset: u64,
    pub fields: Vec<FieldRec>,
}

pub fn tag(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "RO",
        Access::WriteOnly => "WO",
        Access::ReadWrite => "RW",
        Access::WriteOneToClear => "W1C",
    }
}

pub fn fields_of(r: &Register) -> Vec<FieldRec> {
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
pub fn table_set(map: &BusMap) -> BTreeMap<u64, RegRec> {
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
pub fn table_counts(map: &BusMap) -> (usize, usize) {
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

// ---------------------------------------------------------------------------
// The C header's numbers.

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
pub fn expected_macros(map: &BusMap) -> BTreeMap<String, u64> {
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
            v.push((format!("{P}_{}_{}_NUM", b.name, a.name), u64::from(a.count)));
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

pub fn check_header_numbers(map: &BusMap) -> usize {
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

// ---------------------------------------------------------------------------
// The JSON, parsed back.

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

pub fn check_json(map: &BusMap) -> usize {
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
