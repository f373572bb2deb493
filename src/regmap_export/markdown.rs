//! `REGISTERS.md`: the register map as documentation.

use super::{
    access_rule, access_tag, block_byte_offset, block_span_bytes, map_hash, memory_bytes,
    register_doc, stride_bytes, FSMC_NE1_BASE, REGISTER_BYTES,
};
use motionhdl_hdl::banner;
use motionhdl_model::regmap::{Block, BusMap, Register, RegisterArray};
use std::fmt::Write;

/// The file name (at the top of the generated tree).
pub const FILE_NAME: &str = "REGISTERS.md";

/// `text` safe inside a Markdown table cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

fn hex(v: u32) -> String {
    format!("0x{v:08X}")
}

fn register_row(place: &str, anchor: &str, r: &Register) -> String {
    format!(
        "| {place} | [{}](#{anchor}) | {} | `{}` | {} |\n",
        r.name,
        access_tag(r.access),
        hex(r.reset),
        cell(&register_doc(r))
    )
}

fn anchor(b: &Block, a: Option<&RegisterArray>, r: &Register) -> String {
    match a {
        None => format!("{}-{}", b.name, r.name).to_lowercase(),
        Some(a) => format!("{}-{}-{}", b.name, a.name, r.name).to_lowercase(),
    }
}

fn field_table(o: &mut String, b: &Block, a: Option<&RegisterArray>, r: &Register) {
    let title = match a {
        None => format!("{}.{}", b.name, r.name),
        Some(a) => format!("{}.{}[n].{}", b.name, a.name, r.name),
    };
    let _ = writeln!(o, "<a id=\"{}\"></a>\n#### {title}\n", anchor(b, a, r));
    let _ = writeln!(o, "{}\n", register_doc(r));
    if r.fields.is_empty() {
        o.push_str("No fields.\n\n");
        return;
    }
    o.push_str("| bits | field | access | reset | description |\n");
    o.push_str("| --- | --- | --- | --- | --- |\n");
    for f in &r.fields {
        let mut desc = cell(f.description);
        for v in &f.values {
            let _ = write!(
                desc,
                "<br>`{}` = {}: {}",
                v.name,
                v.value,
                cell(v.description)
            );
        }
        let bits = if f.width == 1 {
            f.lsb.to_string()
        } else {
            format!("{}:{}", f.lsb + f.width - 1, f.lsb)
        };
        let _ = writeln!(
            o,
            "| {bits} | {} | {} | `{:#x}` | {desc} |",
            f.name,
            access_tag(f.access),
            f.reset,
        );
    }
    o.push('\n');
}

/// The map as Markdown.
pub fn markdown(map: &BusMap) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "<!-- {} -->\n", banner());
    let _ = writeln!(o, "# {} register map\n", map.name);
    let _ = writeln!(
        o,
        "{}. ID.MAP_HASH = `{}`. Byte offsets are from the base of the FPGA's \
         {}-byte window; the FPGA usually sits on STM32F4 FSMC bank 1 region 1 (NE1) \
         at `{}`.\n",
        map.description,
        hex(map_hash(map)),
        map.window_bytes(),
        hex(FSMC_NE1_BASE)
    );
    let _ = writeln!(o, "**32-bit access only.** {}\n", access_rule());
    o.push_str(
        "Access: RO read-only (writes ignored), WO write-only (reads return 0), RW \
         read-write, W1C read, write 1 to clear.\n\n",
    );
    o.push_str(
        "## Blocks\n\n| byte offset | block | bytes | description |\n| --- | --- | --- | --- |\n",
    );
    for b in &map.blocks {
        let _ = writeln!(
            o,
            "| `{:#06x}` | [{}](#{}) | {} | {} |",
            block_byte_offset(b),
            b.name,
            b.name.to_lowercase(),
            block_span_bytes(b),
            cell(b.description)
        );
    }
    for m in &map.memories {
        let _ = writeln!(
            o,
            "| `{:#06x}` | [{}](#{}) | {} | {} |",
            m.byte_offset,
            m.name,
            m.name.to_lowercase(),
            memory_bytes(m),
            cell(m.description)
        );
    }
    o.push('\n');

    for b in &map.blocks {
        let base = block_byte_offset(b);
        let _ = writeln!(
            o,
            "<a id=\"{}\"></a>\n## {}\n",
            b.name.to_lowercase(),
            b.name
        );
        let _ = writeln!(
            o,
            "{}. Byte offset `{base:#06x}` from the window base, {} bytes decoded.\n",
            b.description,
            block_span_bytes(b)
        );
        o.push_str("| byte offset | register | access | reset | description |\n");
        o.push_str("| --- | --- | --- | --- | --- |\n");
        let mut rows: Vec<(u32, String)> = Vec::new();
        for r in &b.registers {
            let place = format!("`{:#06x}`", base + r.offset * REGISTER_BYTES);
            rows.push((r.offset, register_row(&place, &anchor(b, None, r), r)));
        }
        for a in &b.arrays {
            for r in &a.registers {
                let first = base + (a.offset + r.offset) * REGISTER_BYTES;
                let place = format!(
                    "`{first:#06x}` + n × `{:#x}` ({}[n], n = 0..{})",
                    stride_bytes(a),
                    a.name,
                    a.count - 1
                );
                rows.push((
                    a.offset + r.offset,
                    register_row(&place, &anchor(b, Some(a), r), r),
                ));
            }
        }
        rows.sort_by_key(|r| r.0);
        for (_, row) in rows {
            o.push_str(&row);
        }
        o.push('\n');
        for a in &b.arrays {
            let _ = writeln!(
                o,
                "{}[n]: {} elements of {} bytes from `{:#06x}`; element n at `{:#06x}` + n × `{:#x}`.\n",
                a.name,
                a.count,
                stride_bytes(a),
                base + a.offset * REGISTER_BYTES,
                base + a.offset * REGISTER_BYTES,
                stride_bytes(a)
            );
        }
        for r in &b.registers {
            field_table(&mut o, b, None, r);
        }
        for a in &b.arrays {
            for r in &a.registers {
                field_table(&mut o, b, Some(a), r);
            }
        }
    }

    for m in &map.memories {
        let _ = writeln!(
            o,
            "<a id=\"{}\"></a>\n## {}\n",
            m.name.to_lowercase(),
            m.name
        );
        let _ = writeln!(
            o,
            "{} Byte offset `{:#06x}` to `{:#06x}`: {} words of {} bits, word n at byte \
             offset `{:#06x}` + {} × n. Access it {}-bit wide, one word per access.\n",
            m.description,
            m.byte_offset,
            m.byte_offset + memory_bytes(m) - 1,
            m.words,
            m.word_bits,
            m.byte_offset,
            m.word_bits / 8,
            m.word_bits
        );
    }
    if map.memories.is_empty() {
        o.push_str(
            "## Shared RAM\n\nThis build keeps the shared RAM outside the FPGA (ID.CONFIG.ISA_RAM \
             = EXTERNAL): there is no RAM window on this bus.\n",
        );
    }
    while o.ends_with("\n\n") {
        o.pop();
    }
    o
}
