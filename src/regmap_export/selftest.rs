//! `motionhdl_regs_selftest.c`: a C program that checks every number of
//! `motionhdl_regs.h` (macros, struct offsets and sizes, register addresses
//! through the window struct) against values computed here from the
//! register table, independently of the header's text.

use super::c_header::{
    array_prefix, block_prefix, block_type, element_type, field_prefix, memory_prefix,
    register_prefix, window_type, FILE_NAME as HEADER, PREFIX,
};
use super::{
    block_byte_offset, block_span_bytes, block_struct_bytes, element_struct_bytes, id_magic,
    instances, map_hash, memory_bytes, stride_bytes, window_layout, FSMC_NE1_BASE, REGISTER_BYTES,
};
use motionhdl_hdl::banner;
use motionhdl_model::regmap::{Block, BusMap, Register, RegisterArray};
use std::fmt::Write;

/// The program's file name (under `test/` in the generated tree).
pub const FILE_NAME: &str = "motionhdl_regs_selftest.c";

/// Longest line of the program.
use crate::c_writer::MAX_LINE;

/// One check: a C expression and the value it must have.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Check {
    pub expr: String,
    pub value: u64,
}

fn push(out: &mut Vec<Check>, expr: String, value: u32) {
    out.push(Check {
        expr,
        value: u64::from(value),
    });
}

fn register_checks(out: &mut Vec<Check>, b: &Block, a: Option<&RegisterArray>, r: &Register) {
    let p = register_prefix(b, a, r);
    push(out, format!("{p}_OFFSET"), r.offset * REGISTER_BYTES);
    push(out, format!("{p}_reset"), r.reset);
    for f in &r.fields {
        let fp = field_prefix(b, a, r, f);
        push(out, format!("{fp}_bm"), f.mask());
        push(out, format!("{fp}_bp"), f.lsb);
        push(out, format!("{fp}_bw"), f.width);
        push(out, format!("{fp}_reset"), f.reset);
        for v in &f.values {
            push(out, format!("{fp}__{}", v.name), v.value);
        }
    }
}

/// Every check the self-test makes, in order.
pub fn checks(map: &BusMap) -> Vec<Check> {
    let p = PREFIX;
    let mut out = Vec::new();
    push(&mut out, format!("{p}_FSMC_NE1_BASE"), FSMC_NE1_BASE);
    push(&mut out, format!("{p}_WINDOW_SIZE"), map.window_bytes());
    push(&mut out, format!("{p}_MAP_HASH"), map_hash(map));
    push(&mut out, format!("{p}_ID_MAGIC"), id_magic(map));
    let clock_hz = u64::from(map.block("ID").register("CLOCK_HZ").reset);
    let hclk_hz = motionhdl_model::fsmc_bridge::STM32F4_HCLK_HZ;
    if let Ok(b) = motionhdl_model::fsmc_bridge::stm32f4_budget_checked(clock_hz, hclk_hz) {
        let t = b.timing;
        push(&mut out, format!("{p}_FSMC_HCLK_HZ"), hclk_hz as u32);
        push(&mut out, format!("{p}_FSMC_ADDSET"), t.addset);
        push(&mut out, format!("{p}_FSMC_DATAST"), t.datast);
        push(&mut out, format!("{p}_FSMC_BUSTURN"), t.busturn);
        push(&mut out, format!("{p}_FSMC_BTR1"), t.btr());
    }
    for b in &map.blocks {
        let bp = block_prefix(b);
        push(&mut out, format!("{bp}_BASE_OFFSET"), block_byte_offset(b));
        push(&mut out, format!("{bp}_SIZE"), block_span_bytes(b));
        for r in &b.registers {
            register_checks(&mut out, b, None, r);
        }
        for a in &b.arrays {
            let ap = array_prefix(b, a);
            push(&mut out, format!("{ap}_NUM"), a.count);
            push(&mut out, format!("{ap}_STRIDE"), stride_bytes(a));
            for i in 0..a.count {
                push(
                    &mut out,
                    format!("{ap}_OFFSET({i})"),
                    (a.offset + i * a.stride) * REGISTER_BYTES,
                );
            }
            for r in &a.registers {
                register_checks(&mut out, b, Some(a), r);
            }
        }
    }
    for m in &map.memories {
        let mp = memory_prefix(m.name);
        push(&mut out, format!("{mp}_BASE_OFFSET"), m.byte_offset);
        push(&mut out, format!("{mp}_WORDS"), m.words);
        push(&mut out, format!("{mp}_WORD_BITS"), m.word_bits);
        push(&mut out, format!("{mp}_SIZE"), memory_bytes(m));
    }

    // The structs: every member's offset and every struct's size.
    for b in &map.blocks {
        let bt = block_type(b);
        for a in &b.arrays {
            let et = element_type(b, a);
            for r in &a.registers {
                push(
                    &mut out,
                    format!("offsetof({et}, {})", r.name),
                    r.offset * REGISTER_BYTES,
                );
            }
            push(&mut out, format!("sizeof({et})"), stride_bytes(a));
            push(
                &mut out,
                format!("offsetof({bt}, {})", a.name),
                a.offset * REGISTER_BYTES,
            );
            assert_eq!(element_struct_bytes(a), stride_bytes(a));
        }
        for r in &b.registers {
            push(
                &mut out,
                format!("offsetof({bt}, {})", r.name),
                r.offset * REGISTER_BYTES,
            );
        }
        push(&mut out, format!("sizeof({bt})"), block_struct_bytes(b));
    }
    let wt = window_type();
    for b in &map.blocks {
        push(
            &mut out,
            format!("offsetof({wt}, {})", b.name),
            block_byte_offset(b),
        );
    }
    for m in &map.memories {
        push(
            &mut out,
            format!("offsetof({wt}, {})", m.name),
            m.byte_offset,
        );
        push(
            &mut out,
            format!("sizeof((({wt} *)0)->{})", m.name),
            memory_bytes(m),
        );
    }
    push(&mut out, format!("sizeof({wt})"), window_layout(map).1);

    // Every register's address through the window struct and through the
    // offset macros, at the default base.
    for i in instances(map) {
        let b = i.block;
        let r = i.register;
        let (member, offset_macros) = match i.array {
            None => (
                format!("{}.{}", b.name, r.name),
                format!(
                    "{}_BASE_OFFSET + {}_OFFSET",
                    block_prefix(b),
                    register_prefix(b, None, r)
                ),
            ),
            Some((a, n)) => (
                format!("{}.{}[{n}].{}", b.name, a.name, r.name),
                format!(
                    "{}_BASE_OFFSET + {}_OFFSET({n}) + {}_OFFSET",
                    block_prefix(b),
                    array_prefix(b, a),
                    register_prefix(b, Some(a), r)
                ),
            ),
        };
        push(
            &mut out,
            format!("(uintptr_t)&{p}({p}_FSMC_NE1_BASE)->{member}"),
            FSMC_NE1_BASE + i.byte_offset,
        );
        push(&mut out, offset_macros, i.byte_offset);
    }
    for m in &map.memories {
        for word in [0, m.words - 1] {
            push(
                &mut out,
                format!("(uintptr_t)&{p}({p}_FSMC_NE1_BASE)->{}[{word}]", m.name),
                FSMC_NE1_BASE + m.byte_offset + word * m.word_bits / 8,
            );
        }
    }
    out
}

/// The self-test program: prints `PASS <n> checks` and exits 0, or prints
/// `FAIL <expression>: ...` for every failing check and exits 1.
pub fn program(map: &BusMap) -> String {
    let checks = checks(map);
    let mut o = String::new();
    let _ = writeln!(o, "/* {} */", banner());
    let _ = write!(
        o,
        "/*
 * {FILE_NAME}: checks every number of {HEADER} against the register
 * table it was generated from ({n} checks): macros, struct member offsets and
 * sizes, and register addresses through the window struct. Build and run:
 *   cc -std=c99 -Wall -Wextra -I include -o selftest test/{FILE_NAME} && ./selftest
 * Prints `PASS {n} checks` and exits 0, or prints each failing check and exits 1.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include \"{HEADER}\"

static unsigned long passed;
static unsigned long failed;

static void check(const char *what, unsigned long long got, unsigned long long want)
{{
    if (got == want) {{
        passed++;
    }} else {{
        failed++;
        printf(\"FAIL %s: got 0x%llx, want 0x%llx\\n\", what, got, want);
    }}
}}

#define EQ(expr, want) check(#expr, (unsigned long long)(expr), (want))

int main(void)
{{
",
        n = checks.len()
    );
    for c in &checks {
        let line = format!("    EQ({}, 0x{:x}ull);", c.expr, c.value);
        if line.len() <= MAX_LINE {
            o.push_str(&line);
            o.push('\n');
            continue;
        }
        // Too long: one term of a sum per line (the C preprocessor turns the
        // line breaks into spaces when it quotes the expression).
        let mut line = String::from("    EQ(");
        for (i, term) in c.expr.split(" + ").enumerate() {
            if i > 0 {
                line.push_str(" +");
                o.push_str(&line);
                o.push('\n');
                line = String::from("       ");
            }
            line.push_str(term);
        }
        let _ = writeln!(o, "{line},\n       0x{:x}ull);", c.value);
    }
    for l in o.lines() {
        assert!(l.len() <= MAX_LINE, "line too long: {l}");
    }
    let _ = write!(
        o,
        "    if (failed != 0) {{
        printf(\"FAILED %lu of %lu checks\\n\", failed, passed + failed);
        return 1;
    }}
    printf(\"PASS %lu checks\\n\", passed);
    return 0;
}}
"
    );
    o
}
