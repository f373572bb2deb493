//! `regmap.json`: the register map, machine-readable, with absolute byte
//! offsets (from the window base). Keys come in a fixed order; the first is
//! `generated_by`.

use super::{
    access_rule, block_byte_offset, block_span_bytes, map_hash, memory_bytes, stride_bytes,
    FSMC_NE1_BASE, REGISTER_BYTES,
};
use motionhdl_hdl::{banner, VERSION};
use motionhdl_model::regmap::{Access, BusMap, Field, Register};

/// The file name (at the top of the generated tree).
pub const FILE_NAME: &str = "regmap.json";

/// The access type as the JSON spells it.
pub fn access(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "read-only",
        Access::WriteOnly => "write-only",
        Access::ReadWrite => "read-write",
        Access::WriteOneToClear => "write-1-to-clear",
    }
}

/// A JSON value, built in order.
enum J {
    Str(String),
    Num(u64),
    Arr(Vec<J>),
    Obj(Vec<(&'static str, J)>),
}

fn s(text: &str) -> J {
    J::Str(text.to_string())
}

fn n(v: u32) -> J {
    J::Num(u64::from(v))
}

fn string(out: &mut String, text: &str) {
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
}

fn write(out: &mut String, v: &J, depth: usize) {
    let pad = |out: &mut String, d: usize| {
        out.push('\n');
        out.push_str(&"  ".repeat(d));
    };
    match v {
        J::Str(t) => string(out, t),
        J::Num(x) => out.push_str(&x.to_string()),
        J::Arr(items) if items.is_empty() => out.push_str("[]"),
        J::Arr(items) if items.iter().all(|i| matches!(i, J::Num(_))) => {
            let t: Vec<String> = items
                .iter()
                .map(|i| match i {
                    J::Num(x) => x.to_string(),
                    _ => unreachable!(),
                })
                .collect();
            out.push('[');
            out.push_str(&t.join(", "));
            out.push(']');
        }
        J::Arr(items) => {
            out.push('[');
            for (k, i) in items.iter().enumerate() {
                if k > 0 {
                    out.push(',');
                }
                pad(out, depth + 1);
                write(out, i, depth + 1);
            }
            pad(out, depth);
            out.push(']');
        }
        J::Obj(members) => {
            out.push('{');
            for (k, (key, value)) in members.iter().enumerate() {
                if k > 0 {
                    out.push(',');
                }
                pad(out, depth + 1);
                string(out, key);
                out.push_str(": ");
                write(out, value, depth + 1);
            }
            pad(out, depth);
            out.push('}');
        }
    }
}

fn field(f: &Field) -> J {
    J::Obj(vec![
        ("name", s(f.name)),
        ("lsb", n(f.lsb)),
        ("width", n(f.width)),
        ("mask", n(f.mask())),
        ("access", s(access(f.access))),
        ("reset", n(f.reset)),
        ("description", s(f.description)),
        (
            "values",
            J::Arr(
                f.values
                    .iter()
                    .map(|v| {
                        J::Obj(vec![
                            ("name", s(v.name)),
                            ("value", n(v.value)),
                            ("description", s(v.description)),
                        ])
                    })
                    .collect(),
            ),
        ),
    ])
}

/// A register; `place` is its byte offset (absolute for a block register),
/// or for array registers its offset in the element and the absolute byte
/// offset in every element.
fn register(r: &Register, place: Vec<(&'static str, J)>) -> J {
    let mut m = vec![("name", s(r.name))];
    m.extend(place);
    m.extend([
        ("access", s(access(r.access))),
        ("reset", n(r.reset)),
        ("description", s(r.description)),
        ("side_effects", s(r.side_effects)),
        ("fields", J::Arr(r.fields.iter().map(field).collect())),
    ]);
    J::Obj(m)
}

/// The map as JSON text.
pub fn json(map: &BusMap) -> String {
    let blocks = map
        .blocks
        .iter()
        .map(|b| {
            let base = block_byte_offset(b);
            J::Obj(vec![
                ("name", s(b.name)),
                ("description", s(b.description)),
                ("byte_offset", n(base)),
                ("size_bytes", n(block_span_bytes(b))),
                (
                    "registers",
                    J::Arr(
                        b.registers
                            .iter()
                            .map(|r| {
                                register(
                                    r,
                                    vec![("byte_offset", n(base + r.offset * REGISTER_BYTES))],
                                )
                            })
                            .collect(),
                    ),
                ),
                (
                    "arrays",
                    J::Arr(
                        b.arrays
                            .iter()
                            .map(|a| {
                                let first = base + a.offset * REGISTER_BYTES;
                                J::Obj(vec![
                                    ("name", s(a.name)),
                                    ("count", n(a.count)),
                                    ("byte_offset", n(first)),
                                    ("stride_bytes", n(stride_bytes(a))),
                                    (
                                        "registers",
                                        J::Arr(
                                            a.registers
                                                .iter()
                                                .map(|r| {
                                                    let off = r.offset * REGISTER_BYTES;
                                                    register(
                                                        r,
                                                        vec![
                                                            ("element_offset", n(off)),
                                                            (
                                                                "byte_offsets",
                                                                J::Arr(
                                                                    (0..a.count)
                                                                        .map(|i| {
                                                                            n(first
                                                                                + i * stride_bytes(
                                                                                    a,
                                                                                )
                                                                                + off)
                                                                        })
                                                                        .collect(),
                                                                ),
                                                            ),
                                                        ],
                                                    )
                                                })
                                                .collect(),
                                        ),
                                    ),
                                ])
                            })
                            .collect(),
                    ),
                ),
            ])
        })
        .collect();
    let memories = map
        .memories
        .iter()
        .map(|m| {
            J::Obj(vec![
                ("name", s(m.name)),
                ("description", s(m.description)),
                ("byte_offset", n(m.byte_offset)),
                ("words", n(m.words)),
                ("word_bits", n(m.word_bits)),
                ("size_bytes", n(memory_bytes(m))),
            ])
        })
        .collect();
    let top = J::Obj(vec![
        ("generated_by", s(&banner())),
        ("name", s(map.name)),
        ("version", s(VERSION)),
        ("description", s(map.description)),
        ("map_hash", n(map_hash(map))),
        (
            "bus",
            J::Obj(vec![
                ("data_bits", n(16)),
                ("register_bits", n(32)),
                ("halfword_address_bits", n(map.halfword_address_bits)),
                ("window_bytes", n(map.window_bytes())),
                ("default_base_address", n(FSMC_NE1_BASE)),
                ("access_rule", s(access_rule())),
            ]),
        ),
        ("blocks", J::Arr(blocks)),
        ("memories", J::Arr(memories)),
    ]);
    let mut out = String::new();
    write(&mut out, &top, 0);
    out.push('\n');
    // The banner on the first line, as in every generated file.
    let first = "{\n  \"generated_by\": ";
    assert!(out.starts_with(first));
    out.replacen(first, "{\"generated_by\": ", 1)
}
