//! `motionhdl_isa.h`, the PC-side C header of the ISA bridge: its numbers
//! against the register map, and its form (banner, ASCII, line lengths,
//! its place among the generated files). The header in gcc/g++ is
//! `tests/isa_header_c.rs`.

mod common;

use common::isa::{expected, P};
use common::{c_number, defines};
use motionhdl::artifacts;
use motionhdl::isa_header::{isa_header, FILE_NAME};
use motionhdl_hdl::banner;
use motionhdl_model::isa_bridge as card;
use motionhdl_model::regmap;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[test]
fn every_number_in_the_header_is_the_register_maps() {
    let h = isa_header();
    let defs = defines(&h);
    let mut names: Vec<&String> = defs.iter().map(|d| &d.0).collect();
    names.sort();
    let n = names.len();
    names.dedup();
    assert_eq!(names.len(), n, "a macro is defined twice");

    let mut got = BTreeMap::new();
    for (name, value) in &defs {
        if name.contains('(') {
            continue;
        }
        if name == &format!("{P}_H") {
            assert!(value.is_empty(), "include guard has a value: {value}");
            continue;
        }
        let v =
            c_number(value).unwrap_or_else(|| panic!("{name}: `{value}` is not a plain number"));
        got.insert(name.clone(), v);
    }
    let want: BTreeMap<String, u64> = expected().into_iter().collect();
    assert_eq!(got, want, "numeric #defines against the register map");

    // Registers without fields get no field macros; all with fields do.
    let map = regmap::isa_bridge();
    for r in &map.registers {
        let prefix = format!("{P}_{}__", r.name);
        let fields = got.keys().filter(|k| k.starts_with(&prefix)).count();
        assert_eq!(fields, 4 * r.fields.len(), "{}: field macros", r.name);
    }

    // The map itself against the card as the brief and the model describe it.
    for (name, reg) in [
        ("DATA", card::reg::DATA),
        ("ADDR_CLEAR", card::reg::ADDR_CLEAR),
        ("ADDR_INC", card::reg::ADDR_INC),
        ("STATUS", card::reg::STATUS),
    ] {
        assert_eq!(
            want[&format!("{P}_{name}_OFFSET")],
            u64::from(reg),
            "{name}"
        );
    }
    for (field, mask) in [
        ("ADDR", card::status::ADDR_MASK),
        ("AUTO_INC", card::status::AUTO_INC),
        ("WRAPPED", card::status::WRAPPED),
        ("COLLISION", card::status::COLLISION),
    ] {
        assert_eq!(
            want[&format!("{P}_STATUS__{field}_bm")],
            u64::from(mask),
            "{field}"
        );
    }
    assert_eq!(want[&format!("{P}_RAM_WORDS")], 1024);
    assert_eq!(want[&format!("{P}_ADDR_BITS")], 10);
    assert_eq!(want[&format!("{P}_BASE_PORT_MAX")], 0x3fc);

    // Function-like macros and the function declarations the brief names.
    for want in [
        format!("#define {P}_PORT(base_port, reg_offset) "),
        format!("#define {P}_BASE_PORT(switches) "),
        "void motionhdl_isa_outw(uint16_t port, uint16_t value);".to_string(),
        "uint16_t motionhdl_isa_inw(uint16_t port);".to_string(),
        "#include <stdint.h>".to_string(),
        "#include <stddef.h>".to_string(),
        "extern \"C\" {".to_string(),
    ] {
        assert!(h.contains(&want), "missing `{want}`");
    }
    for f in [
        "status",
        "set_address",
        "clear_address",
        "write_block",
        "read_block",
        "clear_sticky",
    ] {
        let call = format!(" motionhdl_isa_{f}(uint16_t base_port");
        assert!(
            h.lines()
                .any(|l| l.starts_with("static inline ") && l.contains(&call)),
            "helper {f} missing"
        );
    }
    // Every register has its comment, with its description.
    for r in &map.registers {
        assert!(
            h.contains(&format!("{}, port +{}", r.name, r.offset)),
            "{}",
            r.name
        );
    }
}

#[test]
fn header_is_bannered_deterministic_ascii_and_short_lined() {
    let h = isa_header();
    assert_eq!(h, isa_header(), "not deterministic");
    let mut lines = h.lines();
    assert_eq!(lines.next().unwrap(), format!("/* {} */", banner()));
    for (i, l) in lines.enumerate() {
        assert!(l.is_ascii(), "line {}: not ASCII: {l}", i + 2);
    }
    for (i, l) in h.lines().enumerate() {
        assert!(l.chars().count() <= 100, "line {} too long: {l}", i + 1);
        assert!(!l.ends_with(' '), "line {}: trailing space", i + 1);
    }
    assert!(h.ends_with(&format!("#endif /* {P}_H */\n")));
    // Only the generator's numbers: no hex literal outside the #defines.
    for l in h.lines().filter(|l| !l.starts_with("#define ")) {
        assert!(
            !l.contains("0x") || l.starts_with(" *") || l.starts_with("/*"),
            "literal outside a #define: {l}"
        );
    }

    // `motionhdl generate` writes it right after motionhdl_config.h.
    let all = artifacts::without_traces(&Default::default());
    let paths: Vec<PathBuf> = all.iter().map(|a| a.path.clone()).collect();
    let cfg = paths
        .iter()
        .position(|p| p == Path::new("include/motionhdl_config.h"))
        .unwrap();
    assert_eq!(
        paths[cfg + 1],
        Path::new("include").join(FILE_NAME),
        "order of generated files"
    );
    assert_eq!(all[cfg + 1].contents, h.as_bytes());
}
