//! `motionhdl_regs.rs`: the register map as a `no_std` Rust module for Rust
//! firmware: one module per block, register and field, holding offsets,
//! masks, positions, widths, reset and enumerated values, plus volatile
//! read/write helpers.

use super::{
    access_rule, block_byte_offset, block_span_bytes, id_magic, map_hash, memory_bytes,
    register_doc, stride_bytes, FSMC_NE1_BASE, REGISTER_BYTES,
};
use motionhdl_hdl::banner;
use motionhdl_model::regmap::{BusMap, Field, Register};
use std::collections::BTreeSet;
use std::fmt::Write;

/// The file name (under `rust/` in the generated tree).
pub const FILE_NAME: &str = "motionhdl_regs.rs";

const MAX_LINE: usize = 100;

/// A table name as a Rust module name: lower case, raw if a keyword.
pub fn module_name(name: &str) -> String {
    let n = name.to_lowercase();
    assert!(
        !["self", "super", "crate", "_"].contains(&n.as_str()),
        "{name} cannot be a module name"
    );
    const KEYWORDS: &[&str] = &[
        "as", "async", "await", "break", "const", "continue", "dyn", "else", "enum", "extern",
        "false", "fn", "for", "gen", "if", "impl", "in", "let", "loop", "match", "mod", "move",
        "mut", "pub", "ref", "return", "static", "struct", "trait", "true", "try", "type",
        "unsafe", "use", "where", "while", "abstract", "become", "box", "do", "final", "macro",
        "override", "priv", "typeof", "unsized", "virtual", "yield",
    ];
    if KEYWORDS.contains(&n.as_str()) {
        format!("r#{n}")
    } else {
        n
    }
}

/// A hex literal in groups of four digits, at least `digits` digits.
pub fn hex(v: u32, digits: usize) -> String {
    let h = format!("{v:0digits$x}");
    let mut groups: Vec<&str> = Vec::new();
    let mut end = h.len();
    while end > 0 {
        let start = end.saturating_sub(4);
        groups.push(&h[start..end]);
        end = start;
    }
    groups.reverse();
    format!("0x{}", groups.join("_"))
}

struct Out {
    text: String,
    depth: usize,
}

impl Out {
    fn indent(&self) -> String {
        "    ".repeat(self.depth)
    }
    fn doc(&mut self, text: &str) {
        let ind = self.indent();
        for line in super::wrap(text, MAX_LINE - ind.len() - 4) {
            if line.is_empty() {
                let _ = writeln!(self.text, "{ind}///");
            } else {
                let _ = writeln!(self.text, "{ind}/// {line}");
            }
        }
    }
    fn line(&mut self, line: &str) {
        let ind = self.indent();
        let l = format!("{ind}{line}");
        assert!(l.len() <= MAX_LINE, "line too long: {l}");
        self.text.push_str(&l);
        self.text.push('\n');
    }
    fn open(&mut self, name: &str, doc: &str, names: &mut BTreeSet<String>) {
        assert!(names.insert(name.to_string()), "module {name} twice");
        self.doc(doc);
        self.line(&format!("pub mod {} {{", module_name(name)));
        self.depth += 1;
    }
    fn close(&mut self) {
        self.depth -= 1;
        self.line("}");
    }
    fn constant(&mut self, names: &mut BTreeSet<String>, name: &str, ty: &str, value: String) {
        assert!(names.insert(name.to_string()), "constant {name} twice");
        self.line(&format!("pub const {name}: {ty} = {value};"));
    }
}

fn field(o: &mut Out, names: &mut BTreeSet<String>, r: &Register, f: &Field) {
    o.open(
        f.name,
        &format!(
            "{}.{}, {}, {}: {}",
            r.name,
            f.name,
            super::bits_text(f.lsb, f.width),
            super::access_text(f.access),
            f.description
        ),
        names,
    );
    let mut consts = BTreeSet::new();
    o.doc("Mask of the field in the register.");
    o.constant(&mut consts, "MASK", "u32", hex(f.mask(), 8));
    o.doc("Bit position of the field's least significant bit.");
    o.constant(&mut consts, "POS", "u32", f.lsb.to_string());
    o.doc("Width in bits.");
    o.constant(&mut consts, "WIDTH", "u32", f.width.to_string());
    o.doc("Reset value (unshifted, as are the enumerated values below).");
    o.constant(&mut consts, "RESET", "u32", hex(f.reset, 1));
    for v in &f.values {
        o.doc(v.description);
        o.constant(&mut consts, v.name, "u32", v.value.to_string());
    }
    o.close();
}

fn register(o: &mut Out, names: &mut BTreeSet<String>, r: &Register, offset_doc: &str) {
    o.open(
        r.name,
        &format!(
            "{}, {}: {}",
            r.name,
            super::access_text(r.access),
            register_doc(r)
        ),
        names,
    );
    let mut inner = BTreeSet::new();
    o.doc(offset_doc);
    o.constant(
        &mut inner,
        "OFFSET",
        "usize",
        hex(r.offset * REGISTER_BYTES, 4),
    );
    o.doc("Reset value of the whole register.");
    o.constant(&mut inner, "RESET", "u32", hex(r.reset, 8));
    let mut fields = BTreeSet::new();
    for f in &r.fields {
        field(o, &mut fields, r, f);
    }
    o.close();
}

/// The map as a `no_std` Rust module.
pub fn module(map: &BusMap) -> String {
    let mut o = Out {
        text: String::new(),
        depth: 0,
    };
    let _ = writeln!(o.text, "// {}", banner());
    for line in super::wrap(
        &format!(
            "{FILE_NAME}: {} - register map for Rust firmware, from the register table with \
             ID.MAP_HASH {:#010x}. no_std, no dependencies: use it as a module (`mod \
             motionhdl_regs;`) or `include!` it. Offsets are in bytes; one module per block, \
             register and field.\n\n{}",
            map.description,
            map_hash(map),
            access_rule()
        ),
        MAX_LINE - 3,
    ) {
        if line.is_empty() {
            o.text.push_str("//\n");
        } else {
            let _ = writeln!(o.text, "// {line}");
        }
    }
    o.text.push('\n');
    let mut top = BTreeSet::new();
    o.doc(
        "Where the FPGA usually sits: STM32F4 FSMC bank 1, region 1 (chip select NE1). Use \
         the base of the bank your board wires the FPGA's chip select to.",
    );
    o.constant(&mut top, "FSMC_NE1_BASE", "usize", hex(FSMC_NE1_BASE, 8));
    o.doc("Bytes the window decodes from its base.");
    o.constant(&mut top, "WINDOW_SIZE", "usize", hex(map.window_bytes(), 4));
    o.doc("Expected ID.MAP_HASH: a different value means another register map.");
    o.constant(&mut top, "MAP_HASH", "u32", hex(map_hash(map), 8));
    o.doc("Expected ID.MAGIC (\"MHDL\" in ASCII).");
    o.constant(&mut top, "ID_MAGIC", "u32", hex(id_magic(map), 8));
    o.text.push('\n');
    o.text.push_str(
        "/// Reads the 32-bit register at byte `offset` from `base` with one 32-bit volatile
/// access (two FSMC halfword cycles, the low halfword first).
///
/// # Safety
///
/// `base` must be the address the window is mapped at, with the FSMC set up, and `offset`
/// the byte offset of a register.
#[inline(always)]
pub unsafe fn read32(base: usize, offset: usize) -> u32 {
    // SAFETY: the caller keeps the contract above (edition 2024 wants
    // the unsafe operation in a block of its own).
    unsafe { core::ptr::read_volatile((base + offset) as *const u32) }
}

/// Writes the 32-bit register at byte `offset` from `base` with one 32-bit volatile access.
///
/// # Safety
///
/// As for [`read32`].
#[inline(always)]
pub unsafe fn write32(base: usize, offset: usize, value: u32) {
    // SAFETY: as for `read32`.
    unsafe { core::ptr::write_volatile((base + offset) as *mut u32, value) }
}

/// Reads the 16-bit memory word at byte `offset` from `base` (one halfword access).
///
/// # Safety
///
/// `base` must be the address the window is mapped at, with the FSMC set up, and `offset`
/// the byte offset of a word of a memory window.
#[inline(always)]
pub unsafe fn read16(base: usize, offset: usize) -> u16 {
    // SAFETY: the caller keeps the contract above.
    unsafe { core::ptr::read_volatile((base + offset) as *const u16) }
}

/// Writes the 16-bit memory word at byte `offset` from `base` (one halfword access).
///
/// # Safety
///
/// As for [`read16`].
#[inline(always)]
pub unsafe fn write16(base: usize, offset: usize, value: u16) {
    // SAFETY: as for `read16`.
    unsafe { core::ptr::write_volatile((base + offset) as *mut u16, value) }
}

",
    );
    let mut modules = BTreeSet::new();
    for b in &map.blocks {
        o.open(
            b.name,
            &format!("{}: {}.", b.name, b.description),
            &mut modules,
        );
        let mut inner = BTreeSet::new();
        let mut subs = BTreeSet::new();
        o.doc("Byte offset of the block from the window base.");
        o.constant(
            &mut inner,
            "BASE_OFFSET",
            "usize",
            hex(block_byte_offset(b), 4),
        );
        o.doc("Bytes the block decodes.");
        o.constant(&mut inner, "SIZE", "usize", hex(block_span_bytes(b), 4));
        for r in &b.registers {
            register(&mut o, &mut subs, r, "Byte offset within the block.");
        }
        for a in &b.arrays {
            o.open(
                a.name,
                &format!(
                    "{}[0..{}]: {} elements of {} bytes.",
                    a.name,
                    a.count - 1,
                    a.count,
                    stride_bytes(a)
                ),
                &mut subs,
            );
            let mut ac = BTreeSet::new();
            o.doc("Number of elements.");
            o.constant(&mut ac, "LEN", "usize", a.count.to_string());
            o.doc("Bytes between elements.");
            o.constant(&mut ac, "STRIDE", "usize", hex(stride_bytes(a), 4));
            o.doc("Byte offset of element 0 within the block.");
            o.constant(
                &mut ac,
                "OFFSET",
                "usize",
                hex(a.offset * REGISTER_BYTES, 4),
            );
            o.doc("Byte offset of element `n` within the block.");
            o.line("pub const fn offset(n: usize) -> usize {");
            o.line("    OFFSET + n * STRIDE");
            o.line("}");
            let mut regs = BTreeSet::new();
            for r in &a.registers {
                register(&mut o, &mut regs, r, "Byte offset within one element.");
            }
            o.close();
        }
        o.close();
    }
    for m in &map.memories {
        o.open(
            m.name,
            &format!("{}: {}", m.name, m.description),
            &mut modules,
        );
        let mut inner = BTreeSet::new();
        o.doc("Byte offset of word 0 from the window base.");
        o.constant(&mut inner, "BASE_OFFSET", "usize", hex(m.byte_offset, 4));
        o.doc("Words in the window.");
        o.constant(&mut inner, "WORDS", "usize", m.words.to_string());
        o.doc("Bits per word; one access per word.");
        o.constant(&mut inner, "WORD_BITS", "u32", m.word_bits.to_string());
        o.doc("Bytes in the window.");
        o.constant(&mut inner, "SIZE", "usize", hex(memory_bytes(m), 4));
        o.close();
    }
    o.text
}
