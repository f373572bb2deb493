//! `motionhdl.svd`: the register map as a CMSIS-SVD 1.3 device description,
//! for debuggers (register views) and code generators such as svd2rust.

use super::{
    block_byte_offset, block_span_bytes, memory_bytes, register_doc, stride_bytes, FSMC_NE1_BASE,
    REGISTER_BYTES,
};
use motionhdl_hdl::{banner, VERSION};
use motionhdl_model::regmap::{Access, BusMap, Field, Register};
use std::fmt::Write;

/// The file name (at the top of the generated tree).
pub const FILE_NAME: &str = "motionhdl.svd";

/// `text` with XML's special characters escaped.
pub fn escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&apos;"),
            c => s.push(c),
        }
    }
    s
}

/// SVD's `<access>` value.
pub fn access(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "read-only",
        Access::WriteOnly => "write-only",
        Access::ReadWrite | Access::WriteOneToClear => "read-write",
    }
}

struct Xml {
    text: String,
    depth: usize,
}

impl Xml {
    fn open(&mut self, tag: &str) {
        let _ = writeln!(self.text, "{:w$}<{tag}>", "", w = 2 * self.depth);
        self.depth += 1;
    }
    fn close(&mut self, tag: &str) {
        self.depth -= 1;
        let _ = writeln!(self.text, "{:w$}</{tag}>", "", w = 2 * self.depth);
    }
    fn leaf(&mut self, tag: &str, value: &str) {
        let _ = writeln!(
            self.text,
            "{:w$}<{tag}>{}</{tag}>",
            "",
            escape(value),
            w = 2 * self.depth
        );
    }
}

fn hex(v: u32) -> String {
    format!("0x{v:08X}")
}

fn field(x: &mut Xml, f: &Field) {
    x.open("field");
    x.leaf("name", f.name);
    x.leaf("description", f.description);
    x.leaf("bitOffset", &f.lsb.to_string());
    x.leaf("bitWidth", &f.width.to_string());
    x.leaf("access", access(f.access));
    if f.access == Access::WriteOneToClear {
        x.leaf("modifiedWriteValues", "oneToClear");
    }
    if !f.values.is_empty() {
        x.open("enumeratedValues");
        for v in &f.values {
            x.open("enumeratedValue");
            x.leaf("name", v.name);
            x.leaf("description", v.description);
            x.leaf("value", &v.value.to_string());
            x.close("enumeratedValue");
        }
        x.close("enumeratedValues");
    }
    x.close("field");
}

fn register(x: &mut Xml, r: &Register) {
    x.open("register");
    x.leaf("name", r.name);
    x.leaf("description", &register_doc(r));
    x.leaf(
        "addressOffset",
        &format!("0x{:X}", r.offset * REGISTER_BYTES),
    );
    x.leaf("size", "32");
    x.leaf("access", access(r.access));
    x.leaf("resetValue", &hex(r.reset));
    x.leaf("resetMask", &hex(u32::MAX));
    if r.access == Access::WriteOneToClear {
        x.leaf("modifiedWriteValues", "oneToClear");
    }
    if !r.fields.is_empty() {
        x.open("fields");
        for f in &r.fields {
            field(x, f);
        }
        x.close("fields");
    }
    x.close("register");
}

/// The CMSIS-SVD 1.3 description of `map`, its peripherals at
/// `FSMC_NE1_BASE` plus their byte offsets.
pub fn svd(map: &BusMap) -> String {
    let mut x = Xml {
        text: String::new(),
        depth: 0,
    };
    // The banner comes first, so the file has no XML declaration (optional;
    // the encoding is UTF-8, XML's default).
    let _ = writeln!(x.text, "<!-- {} -->", banner());
    x.text.push_str(
        "<device schemaVersion=\"1.3\" xmlns:xs=\"http://www.w3.org/2001/XMLSchema-instance\" \
         xs:noNamespaceSchemaLocation=\"CMSIS-SVD.xsd\">\n",
    );
    x.depth = 1;
    x.leaf("vendor", "motionhdl");
    x.leaf("name", map.name);
    x.leaf("version", VERSION);
    x.leaf(
        "description",
        &format!(
            "{}. Base address: STM32F4 FSMC bank 1 region 1 (NE1); move every peripheral \
             for another chip select. {}",
            map.description,
            super::access_rule()
        ),
    );
    x.leaf("addressUnitBits", "8");
    x.leaf("width", "32");
    x.leaf("size", "32");
    x.leaf("access", "read-write");
    x.leaf("resetValue", &hex(0));
    x.leaf("resetMask", &hex(u32::MAX));
    x.open("peripherals");
    for b in &map.blocks {
        x.open("peripheral");
        x.leaf("name", b.name);
        x.leaf("description", b.description);
        x.leaf("groupName", map.name);
        x.leaf("baseAddress", &hex(FSMC_NE1_BASE + block_byte_offset(b)));
        x.open("addressBlock");
        x.leaf("offset", "0x0");
        x.leaf("size", &format!("0x{:X}", block_span_bytes(b)));
        x.leaf("usage", "registers");
        x.close("addressBlock");
        x.open("registers");
        let mut items: Vec<(u32, Option<usize>, Option<usize>)> = b
            .registers
            .iter()
            .enumerate()
            .map(|(i, r)| (r.offset, Some(i), None))
            .chain(
                b.arrays
                    .iter()
                    .enumerate()
                    .map(|(i, a)| (a.offset, None, Some(i))),
            )
            .collect();
        items.sort();
        for (_, r, a) in items {
            if let Some(r) = r {
                register(&mut x, &b.registers[r]);
            }
            if let Some(a) = a {
                let a = &b.arrays[a];
                x.open("cluster");
                x.leaf("dim", &a.count.to_string());
                x.leaf("dimIncrement", &format!("0x{:X}", stride_bytes(a)));
                x.leaf("dimIndex", &format!("0-{}", a.count - 1));
                x.leaf("name", &format!("{}[%s]", a.name));
                x.leaf(
                    "description",
                    &format!("{} {}: {} elements", b.name, a.name, a.count),
                );
                x.leaf(
                    "addressOffset",
                    &format!("0x{:X}", a.offset * REGISTER_BYTES),
                );
                for r in &a.registers {
                    register(&mut x, r);
                }
                x.close("cluster");
            }
        }
        x.close("registers");
        x.close("peripheral");
    }
    for m in &map.memories {
        x.open("peripheral");
        x.leaf("name", m.name);
        x.leaf("description", m.description);
        x.leaf("groupName", map.name);
        x.leaf("baseAddress", &hex(FSMC_NE1_BASE + m.byte_offset));
        x.open("addressBlock");
        x.leaf("offset", "0x0");
        x.leaf("size", &format!("0x{:X}", memory_bytes(m)));
        x.leaf("usage", "buffer");
        x.close("addressBlock");
        x.open("registers");
        x.open("register");
        x.leaf("dim", &m.words.to_string());
        x.leaf("dimIncrement", &format!("0x{:X}", m.word_bits / 8));
        x.leaf("name", "WORD[%s]");
        x.leaf(
            "description",
            &format!(
                "One {}-bit word; access it as a {}-bit halfword.",
                m.word_bits, m.word_bits
            ),
        );
        x.leaf("addressOffset", "0x0");
        x.leaf("size", &m.word_bits.to_string());
        x.leaf("access", "read-write");
        x.leaf("resetValue", &hex(0));
        // The RAM's contents after reset are not defined.
        x.leaf("resetMask", &hex(0));
        x.close("register");
        x.close("registers");
        x.close("peripheral");
    }
    x.close("peripherals");
    x.text.push_str("</device>\n");
    x.text
}
