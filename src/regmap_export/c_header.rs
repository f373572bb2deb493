//! `motionhdl_regs.h`: the MCU firmware's C header for the register map,
//! with PeakRDL-style macro names and CMSIS-style register structs.

use super::{
    access_rule, bits_text, block_byte_offset, block_span_bytes, id_magic, layout, map_hash,
    memory_bytes, register_doc, stride_bytes, window_layout, Member, WindowMember, FSMC_NE1_BASE,
    REGISTER_BYTES,
};
use crate::c_writer::{self, IntWidth};
use motionhdl_hdl::banner;
use motionhdl_model::fsmc_bridge;
use motionhdl_model::regmap::{Access, Block, BusMap, Field, Register, RegisterArray};
use std::collections::BTreeSet;
use std::fmt::Write;

/// The header's file name (under `include/` in the generated tree).
pub const FILE_NAME: &str = "motionhdl_regs.h";

/// Prefix of every macro and type.
pub const PREFIX: &str = "MOTIONHDL";

/// `MOTIONHDL_<BLOCK>`.
pub fn block_prefix(b: &Block) -> String {
    format!("{PREFIX}_{}", b.name)
}

/// `MOTIONHDL_<BLOCK>_<ARRAY>`.
pub fn array_prefix(b: &Block, a: &RegisterArray) -> String {
    format!("{PREFIX}_{}_{}", b.name, a.name)
}

/// `MOTIONHDL_<BLOCK>[_<ARRAY>]_<REG>`.
pub fn register_prefix(b: &Block, a: Option<&RegisterArray>, r: &Register) -> String {
    match a {
        None => format!("{}_{}", block_prefix(b), r.name),
        Some(a) => format!("{}_{}", array_prefix(b, a), r.name),
    }
}

/// `MOTIONHDL_<BLOCK>[_<ARRAY>]_<REG>__<FIELD>`.
pub fn field_prefix(b: &Block, a: Option<&RegisterArray>, r: &Register, f: &Field) -> String {
    format!("{}__{}", register_prefix(b, a, r), f.name)
}

/// `MOTIONHDL_<MEMORY>`.
pub fn memory_prefix(name: &str) -> String {
    format!("{PREFIX}_{name}")
}

/// Type name of a block's struct.
pub fn block_type(b: &Block) -> String {
    format!("{}_TypeDef", block_prefix(b))
}

/// Type name of an array element's struct.
pub fn element_type(b: &Block, a: &RegisterArray) -> String {
    format!("{}_TypeDef", array_prefix(b, a))
}

/// Type name of the whole window's struct.
pub fn window_type() -> String {
    format!("{PREFIX}_TypeDef")
}

/// A value as an unsigned C literal: hex, at least 4 digits.
pub fn hex(v: u32) -> String {
    IntWidth::Bits32.hex(v)
}

fn dec(v: u32) -> String {
    IntWidth::Bits32.dec(v)
}

fn qualifier(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "__I ",
        Access::WriteOnly => "__O ",
        Access::ReadWrite | Access::WriteOneToClear => "__IO",
    }
}

struct Out {
    text: String,
    names: BTreeSet<String>,
}

impl Out {
    /// `text` as a C block comment, wrapped; one line when it fits.
    fn comment(&mut self, indent: &str, text: &str) {
        c_writer::comment(&mut self.text, indent, text);
    }

    fn define(&mut self, name: &str, value: &str) {
        let key = name.split('(').next().unwrap().to_string();
        assert!(self.names.insert(key), "macro {name} defined twice");
        c_writer::define(&mut self.text, name, value);
    }

    fn line(&mut self, line: &str) {
        c_writer::line(&mut self.text, line);
    }
}

fn field_defines(o: &mut Out, b: &Block, a: Option<&RegisterArray>, r: &Register, f: &Field) {
    let p = field_prefix(b, a, r, f);
    let mut text = format!(
        "{}.{}, {}, {}: {}",
        r.name,
        f.name,
        bits_text(f.lsb, f.width),
        super::access_text(f.access),
        f.description
    );
    if !f.values.is_empty() {
        text.push_str(" Values (unshifted): ");
        let v: Vec<String> = f
            .values
            .iter()
            .map(|v| format!("{} = {}: {}", v.name, v.value, v.description))
            .collect();
        text.push_str(&v.join(" "));
    }
    o.comment("", &text);
    o.define(&format!("{p}_bm"), &hex(f.mask()));
    o.define(&format!("{p}_bp"), &dec(f.lsb));
    o.define(&format!("{p}_bw"), &dec(f.width));
    o.define(&format!("{p}_reset"), &hex(f.reset));
    for v in &f.values {
        o.define(&format!("{p}__{}", v.name), &dec(v.value));
    }
}

fn register_defines(o: &mut Out, b: &Block, a: Option<&RegisterArray>, r: &Register) {
    let p = register_prefix(b, a, r);
    let place = match a {
        None => format!("block +{:#05x}", r.offset * REGISTER_BYTES),
        Some(a) => format!("{}[n] +{:#04x}", a.name, r.offset * REGISTER_BYTES),
    };
    o.comment(
        "",
        &format!(
            "{}{} ({place}), {}: {}",
            a.map(|a| format!("{}[n].", a.name)).unwrap_or_default(),
            r.name,
            super::access_text(r.access),
            register_doc(r)
        ),
    );
    o.define(&format!("{p}_OFFSET"), &hex(r.offset * REGISTER_BYTES));
    o.define(&format!("{p}_reset"), &hex(r.reset));
    for f in &r.fields {
        field_defines(o, b, a, r, f);
    }
    o.text.push('\n');
}

/// The struct body of `registers` and `arrays`; `size` pads it.
fn struct_body(
    o: &mut Out,
    b: &Block,
    registers: &[Register],
    arrays: &[RegisterArray],
    size: Option<u32>,
) {
    let (members, _) = layout(registers, arrays, size);
    let mut reserved = 0;
    for (offset, m) in members {
        let at = offset * REGISTER_BYTES;
        match m {
            Member::Register(r) => o.line(&format!(
                "    {} uint32_t {}; /* +{at:#05x} {} */",
                qualifier(r.access),
                r.name,
                super::access_tag(r.access)
            )),
            Member::Array(a) => o.line(&format!(
                "    {} {}[{}_NUM]; /* +{at:#05x} */",
                element_type(b, a),
                a.name,
                array_prefix(b, a)
            )),
            Member::Reserved { words } => {
                o.line(&format!(
                    "    uint32_t RESERVED{reserved}[{words}]; /* +{at:#05x} */"
                ));
                reserved += 1;
            }
        }
    }
}

/// The MCU register map as a C header (`motionhdl_regs.h`), for C99 or
/// later and C++.
pub fn header(map: &BusMap) -> String {
    let mut o = Out {
        text: String::new(),
        names: BTreeSet::new(),
    };
    let p = PREFIX;
    let _ = writeln!(o.text, "/* {} */", banner());
    o.comment(
        "",
        &format!(
            "{FILE_NAME}: {} - register map for MCU firmware, generated from the register \
             table with ID.MAP_HASH {:#010x}. For C99 or later, and C++.",
            map.description,
            map_hash(map)
        ),
    );
    let _ = writeln!(o.text, "#ifndef {p}_REGS_H\n#define {p}_REGS_H\n");
    o.text.push_str("#include <stdint.h>\n\n");
    o.text
        .push_str("#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n");
    o.comment(
        "",
        &format!(
            "{}\n\nMacro names: MOTIONHDL_<BLOCK>_BASE_OFFSET is a block's byte offset from the \
             window base; MOTIONHDL_<BLOCK>_<REG>_OFFSET a register's byte offset within its \
             block, or within one element of an array (MOTIONHDL_<BLOCK>_<ARRAY>_OFFSET(n) is \
             element n's byte offset within the block). Per field: _bm mask, _bp bit position, \
             _bw width, _reset reset value (unshifted); MOTIONHDL_..._<REG>__<FIELD>__<VALUE> \
             are a field's enumerated values (unshifted). Firmware reads ID.MAGIC and \
             ID.MAP_HASH first and compares them with MOTIONHDL_ID_MAGIC and \
             MOTIONHDL_MAP_HASH.",
            access_rule()
        ),
    );
    o.text.push('\n');

    o.comment(
        "",
        "CMSIS-style access qualifiers, unless CMSIS defined them: __I read-only, __O \
         write-only, __IO read-write. As in CMSIS, __I is plain volatile in C++.",
    );
    o.text.push_str(
        "#ifndef __I\n#ifdef __cplusplus\n#define __I volatile\n#else\n#define __I volatile const\n\
         #endif\n#endif\n#ifndef __O\n#define __O volatile\n#endif\n#ifndef __IO\n\
         #define __IO volatile\n#endif\n\n",
    );

    o.comment(
        "",
        "Where the FPGA usually sits: STM32F4 FSMC bank 1, region 1 (chip select NE1). \
         Use the base address of the bank your board wires the FPGA's chip select to.",
    );
    o.define(
        &format!("{p}_FSMC_NE1_BASE"),
        &format!("0x{FSMC_NE1_BASE:08x}u"),
    );
    fsmc_timing(&mut o, map);
    o.comment("", "Bytes the window decodes from its base.");
    o.define(&format!("{p}_WINDOW_SIZE"), &hex(map.window_bytes()));
    o.comment(
        "",
        "Expected ID.MAP_HASH: hash of this register map. A different value on the bus means \
         firmware and gateware were built from different maps.",
    );
    o.define(&format!("{p}_MAP_HASH"), &hex(map_hash(map)));
    o.comment("", "Expected ID.MAGIC (\"MHDL\" in ASCII).");
    o.define(&format!("{p}_ID_MAGIC"), &hex(id_magic(map)));
    o.text.push('\n');

    for b in &map.blocks {
        let bp = block_prefix(b);
        o.comment(
            "",
            &format!(
                "==== {}: {} (byte offset {:#06x}, {} bytes decoded) ====",
                b.name,
                b.description,
                block_byte_offset(b),
                block_span_bytes(b)
            ),
        );
        o.define(&format!("{bp}_BASE_OFFSET"), &hex(block_byte_offset(b)));
        o.define(&format!("{bp}_SIZE"), &hex(block_span_bytes(b)));
        o.text.push('\n');
        for r in &b.registers {
            register_defines(&mut o, b, None, r);
        }
        for a in &b.arrays {
            let ap = array_prefix(b, a);
            o.comment(
                "",
                &format!(
                    "{}[0..{}]: {} elements of {} bytes from block +{:#05x}.",
                    a.name,
                    a.count - 1,
                    a.count,
                    stride_bytes(a),
                    a.offset * REGISTER_BYTES
                ),
            );
            // The array's own names must not be a register's (CH has a
            // COUNT register: the element count is CH_NUM, not CH_COUNT).
            for own in ["NUM", "STRIDE", "OFFSET"] {
                assert!(
                    a.registers.iter().all(|r| r.name != own),
                    "{ap}: register {own} would share a name with the array's {ap}_{own}"
                );
            }
            o.define(&format!("{ap}_NUM"), &dec(a.count));
            o.define(&format!("{ap}_STRIDE"), &hex(stride_bytes(a)));
            o.comment(
                "",
                &format!("Byte offset of {}[n] within {}.", a.name, b.name),
            );
            o.define(
                &format!("{ap}_OFFSET(n)"),
                &format!(
                    "({} + (uint32_t)(n) * {ap}_STRIDE)",
                    hex(a.offset * REGISTER_BYTES)
                ),
            );
            o.text.push('\n');
            for r in &a.registers {
                register_defines(&mut o, b, Some(a), r);
            }
        }
    }

    for m in &map.memories {
        let mp = memory_prefix(m.name);
        o.comment(
            "",
            &format!(
                "==== {}: {} ({} words of {} bits) ====",
                m.name, m.description, m.words, m.word_bits
            ),
        );
        o.define(&format!("{mp}_BASE_OFFSET"), &hex(m.byte_offset));
        o.define(&format!("{mp}_WORDS"), &dec(m.words));
        o.define(&format!("{mp}_WORD_BITS"), &dec(m.word_bits));
        o.define(&format!("{mp}_SIZE"), &hex(memory_bytes(m)));
        o.text.push('\n');
    }

    o.comment(
        "",
        "Register structs. Every register member is 32 bits: access it as a whole (see above).",
    );
    for b in &map.blocks {
        for a in &b.arrays {
            o.comment(
                "",
                &format!(
                    "One element of {}.{}: {} bytes.",
                    b.name,
                    a.name,
                    stride_bytes(a)
                ),
            );
            o.line("typedef struct {");
            struct_body(&mut o, b, &a.registers, &[], Some(a.stride));
            o.line(&format!("}} {};\n", element_type(b, a)));
        }
        o.comment("", &format!("{}: {}.", b.name, b.description));
        o.line("typedef struct {");
        struct_body(&mut o, b, &b.registers, &b.arrays, None);
        o.line(&format!("}} {};\n", block_type(b)));
    }
    o.comment("", "The whole window, from its base address.");
    o.line("typedef struct {");
    let (members, _) = window_layout(map);
    let mut reserved = 0;
    for (at, m) in members {
        match m {
            WindowMember::Block(b) => o.line(&format!(
                "    {} {}; /* {at:#06x} */",
                block_type(b),
                b.name
            )),
            WindowMember::Memory(m) => {
                assert_eq!(m.word_bits, 16, "{}: only 16-bit memories", m.name);
                o.line(&format!(
                    "    __IO uint16_t {}[{}_WORDS]; /* {at:#06x} */",
                    m.name,
                    memory_prefix(m.name)
                ))
            }
            WindowMember::Reserved { bytes } => {
                let (t, n) = if bytes % 4 == 0 {
                    ("uint32_t", bytes / 4)
                } else {
                    ("uint8_t", bytes)
                };
                o.line(&format!("    {t} RESERVED{reserved}[{n}]; /* {at:#06x} */"));
                reserved += 1;
            }
            WindowMember::Mirror { of, bytes } => {
                o.line(&format!(
                    "    /* {} again: the RAM port does not decode A10. Do not use. */",
                    of.name
                ));
                o.line(&format!(
                    "    __IO uint16_t {}_MIRROR[{}]; /* {at:#06x} */",
                    of.name,
                    bytes / 2
                ))
            }
            WindowMember::WindowPort { bytes } => {
                o.line("    /* The top's window port (window_addr = A[9:0]): the board's. */");
                o.line(&format!(
                    "    __IO uint16_t WINDOW[{}]; /* {at:#06x} */",
                    bytes / 2
                ))
            }
        }
    }
    o.line(&format!("}} {};\n", window_type()));
    o.comment(
        "",
        "The window at `base`, e.g. MOTIONHDL(MOTIONHDL_FSMC_NE1_BASE)->COUNTER.CH[0].COUNT.",
    );
    o.define(
        &format!("{p}(base)"),
        &format!("(({} *)(uintptr_t)(base))", window_type()),
    );
    let _ = write!(
        o.text,
        "\n#ifdef __cplusplus\n}}\n#endif\n\n#endif /* {p}_REGS_H */\n"
    );
    o.text
}

/// FSMC_BTR1 for the bridge at the gateware's clock (ID.CLOCK_HZ) with an
/// STM32F4 at full speed, or a note saying why there is none.
fn fsmc_timing(o: &mut Out, map: &BusMap) {
    let p = PREFIX;
    let clock_hz = u64::from(map.block("ID").register("CLOCK_HZ").reset);
    let hclk_hz = fsmc_bridge::STM32F4_HCLK_HZ;
    match fsmc_bridge::stm32f4_budget_checked(clock_hz, hclk_hz) {
        Ok(b) => {
            let t = b.timing;
            o.comment(
                "",
                &format!(
                    "FSMC_BTR1 for this gateware ({clock_hz} Hz) with HCLK {hclk_hz} Hz: SRAM mode 1, \
                     16-bit, not multiplexed (docs/fsmc_bridge.md). FSMC_BCR1: MBKEN, MWID = 01, \
                     WREN, EXTMOD = 0. Recompute with a slower HCLK; the read setup time assumed \
                     is THCLK + 4 ns."
                ),
            );
            o.define(&format!("{p}_FSMC_HCLK_HZ"), &format!("{hclk_hz}u"));
            o.define(&format!("{p}_FSMC_ADDSET"), &format!("{}u", t.addset));
            o.define(&format!("{p}_FSMC_DATAST"), &format!("{}u", t.datast));
            o.define(&format!("{p}_FSMC_BUSTURN"), &format!("{}u", t.busturn));
            o.define(&format!("{p}_FSMC_BTR1"), &format!("0x{:08x}u", t.btr()));
        }
        Err(why) => o.comment(
            "",
            &format!("No FSMC setting reaches this gateware: {why}."),
        ),
    }
}
