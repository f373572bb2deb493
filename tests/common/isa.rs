//! The ISA bridge's C header, `motionhdl_isa.h`: the numbers it must
//! define, from the register map, for the tests of `tests/isa_header.rs`
//! and `tests/isa_header_c.rs`.

use motionhdl::isa_header::FILE_NAME;
use motionhdl_model::isa_bridge as card;
use motionhdl_model::regmap::{self, ISA_ADDR_BITS, ISA_RAM_WORDS};

/// The C emulation of the card with base switches `switches`: IsaCard's
/// semantics, with the constants substituted from the model and the map,
/// never from the header. Every port access is logged on stdout as
/// `W port value` / `R port value`, every DSP-side write as `D addr value`.
pub fn emulator_c(switches: u8) -> String {
    let map = regmap::isa_bridge();
    let reg_bits = map.address_bits;
    format!(
        r##"#include <stdio.h>
#include <stddef.h>
#include <stdint.h>

/* The card, as motionhdl_model::isa_bridge::IsaCard; plus COLLISION, which
   only the DSP port sets (emu_collision = 1 stands in for it). The DSP
   side's writes go through emu_dsp_write, logged as `D addr value`. */
#define EMU_SWITCHES {switches}u
#define EMU_SWITCH_MASK {switch_mask}u
#define EMU_REG_BITS {reg_bits}u
#define EMU_REG_MASK {reg_mask}u
#define EMU_WORDS {words}u
#define EMU_ADDR_MASK {addr_mask}u
#define EMU_DATA {r_data}u
#define EMU_ADDR_CLEAR {r_clear}u
#define EMU_ADDR_INC {r_inc}u
#define EMU_STATUS {r_status}u
#define EMU_AUTO_INC {s_auto}u
#define EMU_WRAPPED {s_wrapped}u
#define EMU_COLLISION {s_collision}u
#define EMU_IRQ_EN {s_irq_en}u
#define EMU_BELL {s_bell}u
#define EMU_TO_PC {to_pc}u
#define EMU_TO_DSP {to_dsp}u
#define EMU_UNDRIVEN {undriven}u

static uint16_t emu_ram[EMU_WORDS];
static unsigned emu_addr;
static int emu_auto_inc, emu_wrapped, emu_collision, emu_irq_en, emu_bell, emu_dsp_bell;
static unsigned long emu_misses;

static uint16_t emu_status(void)
{{
    return (uint16_t)(emu_addr | (emu_auto_inc ? EMU_AUTO_INC : 0u)
                      | (emu_wrapped ? EMU_WRAPPED : 0u) | (emu_collision ? EMU_COLLISION : 0u)
                      | (emu_irq_en ? EMU_IRQ_EN : 0u) | (emu_bell ? EMU_BELL : 0u));
}}

/* The card's IRQ line. */
static int emu_irq(void)
{{
    return emu_bell && emu_irq_en;
}}

/* The DSP side writes a word of the shared RAM. */
static void emu_dsp_write(uint16_t addr, uint16_t value)
{{
    printf("D %u %u\n", (unsigned)addr, (unsigned)value);
    emu_ram[addr & EMU_ADDR_MASK] = value;
    if ((addr & EMU_ADDR_MASK) == EMU_TO_PC) {{
        emu_bell = 1;
    }}
}}

static void emu_advance(void)
{{
    if (emu_addr == EMU_ADDR_MASK) {{
        emu_wrapped = 1;
    }}
    emu_addr = (emu_addr + 1u) & EMU_ADDR_MASK;
}}

static void emu_side_effects(unsigned reg)
{{
    if (reg == EMU_DATA && emu_auto_inc) {{
        emu_advance();
    }} else if (reg == EMU_ADDR_CLEAR) {{
        emu_addr = 0;
        emu_wrapped = 0;
    }} else if (reg == EMU_ADDR_INC) {{
        emu_advance();
    }}
}}

static int emu_selected(unsigned port)
{{
    return ((port >> EMU_REG_BITS) & EMU_SWITCH_MASK) == EMU_SWITCHES;
}}

static void emu_outw(uint16_t port, uint16_t value)
{{
    unsigned reg = port & EMU_REG_MASK;
    printf("W %u %u\n", (unsigned)port, (unsigned)value);
    if (!emu_selected(port)) {{
        emu_misses++;
        return;
    }}
    if (reg == EMU_DATA) {{
        emu_ram[emu_addr] = value;
        if (emu_addr == EMU_TO_DSP) {{
            emu_dsp_bell = 1;
        }}
    }} else if (reg == EMU_STATUS) {{
        emu_addr = value & EMU_ADDR_MASK;
        emu_auto_inc = (value & EMU_AUTO_INC) != 0;
        emu_irq_en = (value & EMU_IRQ_EN) != 0;
        if (value & EMU_BELL) {{
            emu_bell = 0;
        }}
        if (value & EMU_WRAPPED) {{
            emu_wrapped = 0;
        }}
        if (value & EMU_COLLISION) {{
            emu_collision = 0;
        }}
    }}
    emu_side_effects(reg);
}}

static uint16_t emu_inw(uint16_t port)
{{
    unsigned reg = port & EMU_REG_MASK;
    uint16_t value;
    if (!emu_selected(port)) {{
        emu_misses++;
        value = (uint16_t)EMU_UNDRIVEN;
    }} else {{
        value = reg == EMU_DATA ? emu_ram[emu_addr] : emu_status();
        if (reg == EMU_DATA && emu_addr == EMU_TO_PC) {{
            emu_bell = 0;
        }}
        emu_side_effects(reg);
    }}
    printf("R %u %u\n", (unsigned)port, (unsigned)value);
    return value;
}}

#ifndef USE_FUNCTIONS
#define MOTIONHDL_ISA_OUTW(port, value) emu_outw((port), (value))
#define MOTIONHDL_ISA_INW(port) emu_inw(port)
#endif
#include "{FILE_NAME}"
#include "{FILE_NAME}" /* the include guard must hold */
#ifdef USE_FUNCTIONS
void motionhdl_isa_outw(uint16_t port, uint16_t value)
{{
    emu_outw(port, value);
}}
uint16_t motionhdl_isa_inw(uint16_t port)
{{
    return emu_inw(port);
}}
#endif
"##,
        reg_mask = (1u32 << reg_bits) - 1,
        words = ISA_RAM_WORDS,
        addr_mask = (1u32 << ISA_ADDR_BITS) - 1,
        r_data = card::reg::DATA,
        r_clear = card::reg::ADDR_CLEAR,
        r_inc = card::reg::ADDR_INC,
        r_status = card::reg::STATUS,
        s_auto = card::status::AUTO_INC,
        s_wrapped = card::status::WRAPPED,
        s_collision = card::status::COLLISION,
        s_irq_en = card::status::IRQ_EN,
        s_bell = card::status::BELL,
        to_pc = card::mailbox::TO_PC,
        to_dsp = card::mailbox::TO_DSP,
        undriven = u16::MAX,
        switch_mask = u8::MAX,
    )
}

pub const P: &str = "MOTIONHDL_ISA";

/// Every number the header must define, by name, from the register map
/// (and the model's port decode), following the header's naming scheme.
pub fn expected() -> Vec<(String, u64)> {
    let map = regmap::isa_bridge();
    let mut v = vec![
        (format!("{P}_RAM_WORDS"), u64::from(ISA_RAM_WORDS)),
        (format!("{P}_ADDR_BITS"), u64::from(ISA_ADDR_BITS)),
        (
            format!("{P}_MAILBOX_TO_PC"),
            u64::from(regmap::ISA_MAILBOX_TO_PC),
        ),
        (
            format!("{P}_MAILBOX_TO_DSP"),
            u64::from(regmap::ISA_MAILBOX_TO_DSP),
        ),
        (format!("{P}_PORT_COUNT"), 1u64 << map.address_bits),
        (
            format!("{P}_BASE_PORT_MAX"),
            u64::from(card::port(u8::MAX, 0)),
        ),
    ];
    for r in &map.registers {
        v.push((format!("{P}_{}_OFFSET", r.name), u64::from(r.offset)));
        v.push((format!("{P}_{}_reset", r.name), u64::from(r.reset)));
        for f in &r.fields {
            let n = format!("{P}_{}__{}", r.name, f.name);
            v.push((format!("{n}_bm"), u64::from(f.mask())));
            v.push((format!("{n}_bp"), u64::from(f.lsb)));
            v.push((format!("{n}_bw"), u64::from(f.width)));
            v.push((format!("{n}_reset"), u64::from(f.reset)));
        }
    }
    v
}
