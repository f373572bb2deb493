//! `REGISTERS.md`, the register map for people: every block, register,
//! field and enumerated value of the table, and the RAM window, in it.

mod common;

use common::regmap::{other_configs, tag};
use motionhdl::regmap_export::markdown;
use motionhdl_model::regmap::mcu_map;
use motionhdl_model::Config;

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
