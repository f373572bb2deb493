//! `regmap.json`: the register map, machine-readable, with absolute byte
//! offsets (from the window base). Keys come in a fixed order (the field
//! order of the structs below); the first is `generated_by`, then the
//! schema it follows and its format version. `regmap.schema.json` (JSON
//! Schema 2020-12) is derived from the same structs, so the two cannot
//! drift apart.

use super::{
    access_rule, block_byte_offset, block_span_bytes, map_hash, memory_bytes, stride_bytes,
    FSMC_NE1_BASE, REGISTER_BYTES,
};
use motionhdl_hdl::{banner, VERSION};
use motionhdl_model::regmap::{Access, Block, BusMap, Field, Memory, Register, RegisterArray};
use schemars::JsonSchema;
use serde::Serialize;
use serde_json::ser::{CompactFormatter, Formatter};
use std::io::{self, Write};

/// The file name (at the top of the generated tree).
pub const FILE_NAME: &str = "regmap.json";
/// The schema's file name, beside it.
pub const SCHEMA_FILE_NAME: &str = "regmap.schema.json";
/// The format's version: raised when a key changes meaning or goes away
/// (new keys in a new place raise it too: the schema refuses unknown ones).
pub const FORMAT_VERSION: u32 = 1;

/// The access type as the JSON spells it.
pub fn access(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "read-only",
        Access::WriteOnly => "write-only",
        Access::ReadWrite => "read-write",
        Access::WriteOneToClear => "write-1-to-clear",
    }
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Map")]
struct MapJ {
    generated_by: String,
    /// The schema this file follows (a path relative to the file).
    #[serde(rename = "$schema")]
    schema: &'static str,
    /// The format's version (FORMAT_VERSION).
    format_version: u32,
    name: &'static str,
    version: &'static str,
    description: &'static str,
    map_hash: u32,
    bus: BusJ,
    blocks: Vec<BlockJ>,
    memories: Vec<MemoryJ>,
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Bus")]
struct BusJ {
    data_bits: u32,
    register_bits: u32,
    halfword_address_bits: u32,
    window_bytes: u32,
    default_base_address: u32,
    access_rule: &'static str,
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Block")]
struct BlockJ {
    name: &'static str,
    description: &'static str,
    byte_offset: u32,
    size_bytes: u32,
    registers: Vec<RegisterJ>,
    arrays: Vec<ArrayJ>,
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Array")]
struct ArrayJ {
    name: &'static str,
    count: u32,
    byte_offset: u32,
    stride_bytes: u32,
    registers: Vec<RegisterJ>,
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Register")]
struct RegisterJ {
    name: &'static str,
    /// Right after the name, as firmware looks a register up by its place.
    #[serde(flatten)]
    place: Place,
    access: &'static str,
    reset: u32,
    description: &'static str,
    side_effects: &'static str,
    fields: Vec<FieldJ>,
}

/// Where a register sits: a block register's absolute byte offset, or an
/// array register's offset in the element and its absolute byte offset in
/// every element.
#[derive(Serialize, JsonSchema)]
#[serde(untagged)]
enum Place {
    Block {
        byte_offset: u32,
    },
    Array {
        element_offset: u32,
        byte_offsets: Vec<u32>,
    },
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Field")]
struct FieldJ {
    name: &'static str,
    lsb: u32,
    width: u32,
    mask: u32,
    access: &'static str,
    reset: u32,
    description: &'static str,
    values: Vec<ValueJ>,
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Value")]
struct ValueJ {
    name: &'static str,
    value: u32,
    description: &'static str,
}

#[derive(Serialize, JsonSchema)]
#[serde(deny_unknown_fields, rename = "Memory")]
struct MemoryJ {
    name: &'static str,
    description: &'static str,
    byte_offset: u32,
    words: u32,
    word_bits: u32,
    size_bytes: u32,
}

fn field(f: &Field) -> FieldJ {
    FieldJ {
        name: f.name,
        lsb: f.lsb,
        width: f.width,
        mask: f.mask(),
        access: access(f.access),
        reset: f.reset,
        description: f.description,
        values: f
            .values
            .iter()
            .map(|v| ValueJ {
                name: v.name,
                value: v.value,
                description: v.description,
            })
            .collect(),
    }
}

fn register(r: &Register, place: Place) -> RegisterJ {
    RegisterJ {
        name: r.name,
        place,
        access: access(r.access),
        reset: r.reset,
        description: r.description,
        side_effects: r.side_effects,
        fields: r.fields.iter().map(field).collect(),
    }
}

fn array(base: u32, a: &RegisterArray) -> ArrayJ {
    let first = base + a.offset * REGISTER_BYTES;
    ArrayJ {
        name: a.name,
        count: a.count,
        byte_offset: first,
        stride_bytes: stride_bytes(a),
        registers: a
            .registers
            .iter()
            .map(|r| {
                let off = r.offset * REGISTER_BYTES;
                let place = Place::Array {
                    element_offset: off,
                    byte_offsets: (0..a.count)
                        .map(|i| first + i * stride_bytes(a) + off)
                        .collect(),
                };
                register(r, place)
            })
            .collect(),
    }
}

fn block(b: &Block) -> BlockJ {
    let base = block_byte_offset(b);
    BlockJ {
        name: b.name,
        description: b.description,
        byte_offset: base,
        size_bytes: block_span_bytes(b),
        registers: b
            .registers
            .iter()
            .map(|r| {
                let place = Place::Block {
                    byte_offset: base + r.offset * REGISTER_BYTES,
                };
                register(r, place)
            })
            .collect(),
        arrays: b.arrays.iter().map(|a| array(base, a)).collect(),
    }
}

fn memory(m: &Memory) -> MemoryJ {
    MemoryJ {
        name: m.name,
        description: m.description,
        byte_offset: m.byte_offset,
        words: m.words,
        word_bits: m.word_bits,
        size_bytes: memory_bytes(m),
    }
}

/// The JSON Schema of `regmap.json`, the banner as its first line.
pub fn schema() -> String {
    let mut schema = schemars::schema_for!(MapJ);
    schema.insert(
        "title".into(),
        format!("motionhdl register map ({FILE_NAME}), format {FORMAT_VERSION}").into(),
    );
    let text = serde_json::to_string_pretty(&schema).expect("a schema serializes");
    let body = text.strip_prefix('{').expect("a schema is an object");
    format!("{{\"$comment\": \"{}\",{body}\n", banner())
}

/// serde_json's pretty layout (two-space indent, `": "`), except that an
/// array whose first element is a number stays on one line,
/// `[32, 96, 160, 224]`: a register's per-element offsets read as one row
/// instead of one line each.
#[derive(Default)]
struct Layout {
    indent: usize,
    /// Per open array: whether it is written on one line.
    one_line: Vec<bool>,
    /// An array's first element comes next; its kind picks the array's
    /// layout, so the line break before it waits until then.
    first_pending: bool,
    /// Whether the innermost open container holds a value yet.
    has_value: bool,
}

impl Layout {
    fn newline<W: ?Sized + Write>(&self, w: &mut W) -> io::Result<()> {
        w.write_all(b"\n")?;
        for _ in 0..self.indent {
            w.write_all(b"  ")?;
        }
        Ok(())
    }

    /// Called before every value.
    fn value<W: ?Sized + Write>(&mut self, w: &mut W, number: bool) -> io::Result<()> {
        if !std::mem::take(&mut self.first_pending) {
            return Ok(());
        }
        if number {
            *self.one_line.last_mut().expect("in an array") = true;
            Ok(())
        } else {
            self.newline(w)
        }
    }
}

/// Each scalar writer: note the value's kind, then write it as serde_json does.
macro_rules! scalar {
    ($($name:ident($t:ty), $number:expr;)*) => {$(
        fn $name<W: ?Sized + Write>(&mut self, w: &mut W, v: $t) -> io::Result<()> {
            self.value(w, $number)?;
            CompactFormatter.$name(w, v)
        }
    )*};
}

impl Formatter for Layout {
    scalar! {
        write_bool(bool), false;
        write_i8(i8), true;
        write_i16(i16), true;
        write_i32(i32), true;
        write_i64(i64), true;
        write_i128(i128), true;
        write_u8(u8), true;
        write_u16(u16), true;
        write_u32(u32), true;
        write_u64(u64), true;
        write_u128(u128), true;
        write_f32(f32), true;
        write_f64(f64), true;
        write_number_str(&str), true;
        write_raw_fragment(&str), false;
    }

    fn write_null<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.value(w, false)?;
        w.write_all(b"null")
    }

    fn begin_string<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.value(w, false)?;
        w.write_all(b"\"")
    }

    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.value(w, false)?;
        self.indent += 1;
        self.has_value = false;
        self.one_line.push(false);
        w.write_all(b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.indent -= 1;
        let one_line = self.one_line.pop().expect("in an array");
        if self.has_value && !one_line {
            self.newline(w)?;
        }
        w.write_all(b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if first {
            self.first_pending = true;
            Ok(())
        } else if *self.one_line.last().expect("in an array") {
            w.write_all(b", ")
        } else {
            w.write_all(b",")?;
            self.newline(w)
        }
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.value(w, false)?;
        self.indent += 1;
        self.has_value = false;
        w.write_all(b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.indent -= 1;
        if self.has_value {
            self.newline(w)?;
        }
        w.write_all(b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if !first {
            w.write_all(b",")?;
        }
        self.newline(w)
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(b": ")
    }

    fn end_object_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }
}

/// The map as JSON text.
pub fn json(map: &BusMap) -> String {
    let top = MapJ {
        generated_by: banner(),
        schema: SCHEMA_FILE_NAME,
        format_version: FORMAT_VERSION,
        name: map.name,
        version: VERSION,
        description: map.description,
        map_hash: map_hash(map),
        bus: BusJ {
            data_bits: 16,
            register_bits: 32,
            halfword_address_bits: map.halfword_address_bits,
            window_bytes: map.window_bytes(),
            default_base_address: FSMC_NE1_BASE,
            access_rule: access_rule(),
        },
        blocks: map.blocks.iter().map(block).collect(),
        memories: map.memories.iter().map(memory).collect(),
    };
    let mut bytes = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut bytes, Layout::default());
    top.serialize(&mut ser).expect("the map serializes");
    let mut out = String::from_utf8(bytes).expect("serde_json writes UTF-8");
    out.push('\n');
    // The banner on the first line, as in every generated file.
    let first = "{\n  \"generated_by\": ";
    assert!(out.starts_with(first));
    out.replacen(first, "{\"generated_by\": ", 1)
}
