//! `motionhdl_isa.h`: the PC-side C header for the ISA bridge, generated
//! from the register map (`motionhdl_model::regmap::isa_bridge`). Every
//! number in it comes from the map or the model; none is typed here.

use motionhdl_hdl::banner;
use motionhdl_model::isa_bridge as card;
use motionhdl_model::regmap::{self, Access, Block, Field, Register};
use std::fmt::Write;

/// The header's file name (under `include/` in the generated tree).
pub const FILE_NAME: &str = "motionhdl_isa.h";

/// Prefix of every macro and function the header defines.
const PREFIX: &str = "MOTIONHDL_ISA";

use crate::c_writer::{IntWidth, MAX_LINE};

/// DOS compilers have a 16-bit `int`: literals past 16 bits are `ul`.
fn hex(v: u32) -> String {
    IntWidth::Bits16.hex(v)
}

fn dec(v: u32) -> String {
    IntWidth::Bits16.dec(v)
}

fn access(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "read-only",
        Access::WriteOnly => "write-only",
        Access::ReadWrite => "read-write",
        Access::WriteOneToClear => "read, write 1 to clear",
    }
}

fn comment(out: &mut String, text: &str) {
    crate::c_writer::comment(out, "", text);
}

fn define(out: &mut String, name: &str, value: &str) {
    crate::c_writer::define(out, name, value);
}

fn offset_name(r: &Register) -> String {
    format!("{PREFIX}_{}_OFFSET", r.name)
}

fn reg_reset_name(r: &Register) -> String {
    format!("{PREFIX}_{}_reset", r.name)
}

fn field_name(r: &Register, f: &Field, suffix: &str) -> String {
    format!("{PREFIX}_{}__{}_{suffix}", r.name, f.name)
}

/// `(A_bm | B_bm)` over the fields of `r` that `pick` selects.
fn masks(r: &Register, pick: impl Fn(&Field) -> bool) -> String {
    let names: Vec<String> = r
        .fields
        .iter()
        .filter(|f| pick(f))
        .map(|f| field_name(r, f, "bm"))
        .collect();
    assert!(!names.is_empty(), "{}: no field selected", r.name);
    format!("({})", names.join(" | "))
}

fn port_note(r: &Register) -> &'static str {
    if r.offset & 1 == 1 {
        " (odd: see the note on byte cycles above)"
    } else {
        ""
    }
}

fn register_defines(out: &mut String, r: &Register) {
    let mut text = format!(
        "{}, port +{}{}, {}: {}",
        r.name,
        r.offset,
        port_note(r),
        access(r.access),
        r.description
    );
    if !r.side_effects.is_empty() {
        text.push(' ');
        text.push_str(r.side_effects);
    }
    comment(out, &text);
    define(out, &offset_name(r), &dec(r.offset));
    define(out, &reg_reset_name(r), &hex(r.reset));
    for f in &r.fields {
        let bits = if f.width == 1 {
            format!("bit {}", f.lsb)
        } else {
            format!("bits {}:{}", f.lsb + f.width - 1, f.lsb)
        };
        comment(
            out,
            &format!(
                "{}.{}, {bits}, {}: {}",
                r.name,
                f.name,
                access(f.access),
                f.description
            ),
        );
        define(out, &field_name(r, f, "bm"), &hex(f.mask()));
        define(out, &field_name(r, f, "bp"), &dec(f.lsb));
        define(out, &field_name(r, f, "bw"), &dec(f.width));
        define(out, &field_name(r, f, "reset"), &hex(f.reset));
    }
    out.push('\n');
}

/// The ISA bridge's register map and access helpers as a C header
/// (`motionhdl_isa.h`), for C99 or later and C++.
pub fn isa_header() -> String {
    isa_header_for(&regmap::isa_bridge())
}

fn isa_header_for(map: &Block) -> String {
    assert!(
        map.arrays.is_empty(),
        "the ISA header has no register arrays"
    );
    let data = map.register("DATA");
    let status = map.register("STATUS");
    let st_addr = status.field("ADDR");
    let st_auto = status.field("AUTO_INC");
    let st_wrapped = status.field("WRAPPED");
    let st_irq_en = status.field("IRQ_EN");
    let st_bell = status.field("BELL");
    let ports = 1u32 << map.address_bits;
    let reg_mask = ports - 1;
    let base_max = u32::from(card::port(u8::MAX, 0));
    let base_step = u32::from(card::port(1, 0)) - u32::from(card::port(0, 0));
    assert_eq!(base_step, ports, "base port step is not the decoded range");
    assert!(map
        .registers
        .iter()
        .all(|r| r.offset < ports && r.fields.iter().all(|f| f.lsb + f.width <= 16)));
    // What the second byte cycle of a split word access at each odd port hits.
    let odd: Vec<String> = map
        .registers
        .iter()
        .filter(|r| r.offset & 1 == 1)
        .map(|r| {
            let next = r.offset + 1;
            let hits = match map.registers.iter().find(|n| n.offset == next) {
                Some(n) => format!("{} (+{next})", n.name),
                None => format!("base+{next}, outside this card"),
            };
            format!(
                "{} (+{}): the second cycle goes to {hits}",
                r.name, r.offset
            )
        })
        .collect();
    let even: Vec<String> = map
        .registers
        .iter()
        .filter(|r| r.offset & 1 == 0)
        .map(|r| format!("{} (+{})", r.name, r.offset))
        .collect();

    let p = PREFIX;
    let so = status.offset;
    let doff = data.offset;
    let dp = offset_name(data);
    let sp = offset_name(status);
    let addr_bm = field_name(status, st_addr, "bm");
    let addr_bp = field_name(status, st_addr, "bp");
    let auto_bm = field_name(status, st_auto, "bm");
    let wrapped_bm = field_name(status, st_wrapped, "bm");
    let irq_en_bm = field_name(status, st_irq_en, "bm");
    let bell_bm = field_name(status, st_bell, "bm");
    let sticky = masks(status, |f| f.access == Access::WriteOneToClear)
        .replace(" | ", "\n                        | ");
    // One mask per line: three names do not fit on one.
    let keep = masks(status, |f| f.access == Access::ReadWrite)
        .replace(" | ", "\n                          | ");

    let mut o = String::new();
    let _ = writeln!(o, "/* {} */", banner());
    comment(
        &mut o,
        &format!(
            "{FILE_NAME}: PC-side access to the motionhdl ISA bridge: {}. For C99 or later, \
             and C++.",
            map.description
        ),
    );
    let _ = writeln!(o, "#ifndef {p}_H\n#define {p}_H\n");
    o.push_str("#include <stddef.h>\n#include <stdint.h>\n\n");
    o.push_str("#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n");
    comment(
        &mut o,
        &format!(
            "The card decodes {ports} registers at I/O port offsets 0..{reg_mask} from its base \
             port (SA1..SA0 select). The base port is the 8 base switches times {ports} \
             (a 74LS688 compares SA9..SA2 with them), so it is a multiple of {ports} in \
             0x000..0x{base_max:03x}.\n\
             Every register access is one 16-bit word (IN/OUT of a word on SD15..SD0; the card \
             asserts IOCS16#). Reads of ADDR_CLEAR and ADDR_INC return STATUS as it was \
             before their action.\n\
             Byte cycles: an AT (16-bit ISA) motherboard splits a 16-bit access to an odd port \
             P into two 8-bit cycles, the low byte at P (on SD15..SD8) and the high byte at \
             P+1 (on SD7..SD0). The card has no SBHE# input and takes each cycle as a whole \
             access of the register it addresses. Odd ports here: {}. Word-aligned: {}.\n\
             The helpers below use only DATA (+{}) and STATUS (+{}); every one of them \
             accesses STATUS, an odd port, so on such a motherboard they do not reach STATUS as \
             one word. Nothing in this header works around that; it is a property of the \
             register layout.",
            odd.join("; "),
            even.join(" and "),
            data.offset,
            status.offset,
        ),
    );
    o.push('\n');

    comment(
        &mut o,
        "Words in the shared RAM, and bits of the address counter.",
    );
    define(
        &mut o,
        &format!("{p}_RAM_WORDS"),
        &dec(regmap::ISA_RAM_WORDS),
    );
    define(
        &mut o,
        &format!("{p}_ADDR_BITS"),
        &dec(regmap::ISA_ADDR_BITS),
    );
    comment(
        &mut o,
        "The doorbells' mailbox words, as on a dual-port RAM such as the IDT7130: the DSP side \
         writes TO_PC to ring the PC (STATUS.BELL, and the IRQ line while STATUS.IRQ_EN is \
         set); the PC's DATA read of TO_PC (or a 1 written to STATUS.BELL) answers it. The PC \
         writes TO_DSP to ring the DSP side. The words hold whatever message the sides agree on.",
    );
    define(
        &mut o,
        &format!("{p}_MAILBOX_TO_PC"),
        &hex(regmap::ISA_MAILBOX_TO_PC),
    );
    define(
        &mut o,
        &format!("{p}_MAILBOX_TO_DSP"),
        &hex(regmap::ISA_MAILBOX_TO_DSP),
    );
    comment(&mut o, "Ports one card decodes, and the highest base port.");
    define(&mut o, &format!("{p}_PORT_COUNT"), &dec(ports));
    define(&mut o, &format!("{p}_BASE_PORT_MAX"), &hex(base_max));
    comment(
        &mut o,
        "The base port for the 8 base-switch bits `switches` (0..255).",
    );
    define(
        &mut o,
        &format!("{p}_BASE_PORT(switches)"),
        &format!("((uint16_t)((switches) * {p}_PORT_COUNT))"),
    );
    comment(
        &mut o,
        "The I/O port of the register at `reg_offset` on the card at `base_port`.",
    );
    define(
        &mut o,
        &format!("{p}_PORT(base_port, reg_offset)"),
        "((uint16_t)((base_port) + (reg_offset)))",
    );
    o.push('\n');

    for r in &map.registers {
        register_defines(&mut o, r);
    }

    comment(
        &mut o,
        "Port I/O: define both MOTIONHDL_ISA_OUTW(port, value) and MOTIONHDL_ISA_INW(port) \
         before including this header, each one 16-bit I/O access. For example, Linux \
         (glibc <sys/io.h>, after ioperm()): #define MOTIONHDL_ISA_OUTW(port, value) \
         outw((value), (port)) and #define MOTIONHDL_ISA_INW(port) inw(port) (note glibc's \
         argument order); DOS (Microsoft C, Open Watcom <conio.h>): outpw(port, value) and \
         inpw(port). If neither is defined, the header declares motionhdl_isa_outw() and \
         motionhdl_isa_inw() for you to implement, and uses them.",
    );
    let _ = write!(
        o,
        "#if defined({p}_OUTW) != defined({p}_INW)
#error \"define both MOTIONHDL_ISA_OUTW and MOTIONHDL_ISA_INW, or neither\"
#endif
#ifndef {p}_OUTW
void motionhdl_isa_outw(uint16_t port, uint16_t value);
uint16_t motionhdl_isa_inw(uint16_t port);
#define {p}_OUTW(port, value) motionhdl_isa_outw((port), (value))
#define {p}_INW(port) motionhdl_isa_inw(port)
#endif

"
    );

    comment(&mut o, &format!("STATUS (one IN at +{so})."));
    let _ = write!(
        o,
        "static inline uint16_t motionhdl_isa_status(uint16_t base_port)
{{
    return (uint16_t){p}_INW({p}_PORT(base_port, {sp}));
}}

"
    );
    comment(
        &mut o,
        &format!(
            "Loads the address counter with `addr` (taken modulo MOTIONHDL_ISA_RAM_WORDS) and \
         sets AUTO_INC if `auto_inc` is nonzero; keeps IRQ_EN, and the sticky bits are left \
         alone (one IN and one OUT at +{so})."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_set_address(uint16_t base_port, uint16_t addr, int auto_inc)
{{
    unsigned v = (((unsigned)addr << {addr_bp}) & {addr_bm})
                 | (motionhdl_isa_status(base_port) & {irq_en_bm});
    if (auto_inc) {{
        v |= {auto_bm};
    }}
    {p}_OUTW({p}_PORT(base_port, {sp}), (uint16_t)v);
}}

"
    );
    comment(
        &mut o,
        &format!(
            "Clears the address counter and STATUS.WRAPPED and keeps AUTO_INC, IRQ_EN, COLLISION \
         and BELL: what an access to ADDR_CLEAR does, done through STATUS (one IN and one OUT \
         at +{so})."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_clear_address(uint16_t base_port)
{{
    unsigned st = motionhdl_isa_status(base_port);
    unsigned v = (st & ({auto_bm} | {irq_en_bm}))
                 | {wrapped_bm};
    {p}_OUTW({p}_PORT(base_port, {sp}), (uint16_t)v);
}}

"
    );
    comment(
        &mut o,
        &format!(
            "Clears the sticky (write-1-to-clear) STATUS bits, BELL among them, and keeps the \
         address counter, IRQ_EN and AUTO_INC (one IN and one OUT at +{so})."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_clear_sticky(uint16_t base_port)
{{
    unsigned st = motionhdl_isa_status(base_port);
    unsigned keep = st & {keep};
    unsigned v = keep | {sticky};
    {p}_OUTW({p}_PORT(base_port, {sp}), (uint16_t)v);
}}

"
    );
    comment(
        &mut o,
        &format!(
            "Writes `n` words from `src` to the RAM from word `start` on: sets the address with \
         AUTO_INC on (motionhdl_isa_set_address), then one OUT at DATA (+{doff}) per word. The counter wraps \
         from the last word to 0 (setting STATUS.WRAPPED); AUTO_INC stays on."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_write_block(uint16_t base_port, uint16_t start,
                                             const uint16_t *src, size_t n)
{{
    uint16_t port = {p}_PORT(base_port, {dp});
    size_t i;
    motionhdl_isa_set_address(base_port, start, 1);
    for (i = 0; i < n; i++) {{
        {p}_OUTW(port, src[i]);
    }}
}}

"
    );
    comment(
        &mut o,
        &format!(
            "Reads `n` words of the RAM from word `start` on into `dst`: sets the address with \
         AUTO_INC on (motionhdl_isa_set_address), then one IN at DATA (+{doff}) per word. Wraps as \
         motionhdl_isa_write_block."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_read_block(uint16_t base_port, uint16_t start,
                                            uint16_t *dst, size_t n)
{{
    uint16_t port = {p}_PORT(base_port, {dp});
    size_t i;
    motionhdl_isa_set_address(base_port, start, 1);
    for (i = 0; i < n; i++) {{
        dst[i] = (uint16_t){p}_INW(port);
    }}
}}

"
    );
    doorbell_helpers(
        &mut o,
        (&format!("+{so}"), &format!("+{doff}")),
        [&sp, &dp, &addr_bm, &auto_bm, &irq_en_bm, &bell_bm],
    );
    let _ = write!(
        o,
        "
#ifdef __cplusplus
}}
#endif

#endif /* {p}_H */
"
    );
    for l in o.lines() {
        assert!(l.chars().count() <= MAX_LINE, "line too long: {l}");
    }
    o
}

/// The IRQ enable and the two doorbells: `so`/`doff` are the port offsets
/// of STATUS and DATA for the comments, `names` the macros of the STATUS
/// and DATA offsets and of the ADDR, AUTO_INC, IRQ_EN and BELL masks.
fn doorbell_helpers(o: &mut String, (so, doff): (&str, &str), names: [&String; 6]) {
    let p = PREFIX;
    let [sp, dp, addr_bm, auto_bm, irq_en_bm, bell_bm] = names;
    comment(
        o,
        &format!(
            "Sets STATUS.IRQ_EN if `on` is nonzero, else clears it: the card drives its IRQ line \
             high while BELL and IRQ_EN are both set. Keeps the address counter and AUTO_INC \
             (one IN and one OUT at {so})."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_enable_irq(uint16_t base_port, int on)
{{
    unsigned st = motionhdl_isa_status(base_port);
    unsigned v = st & ({addr_bm} | {auto_bm});
    if (on) {{
        v |= {irq_en_bm};
    }}
    {p}_OUTW({p}_PORT(base_port, {sp}), (uint16_t)v);
}}

"
    );
    comment(
        o,
        &format!(
            "Rings the DSP side: writes `message` to word MOTIONHDL_ISA_MAILBOX_TO_DSP. Keeps \
             IRQ_EN; leaves AUTO_INC off and the counter at that word (one IN and one OUT at \
             {so}, one OUT at DATA {doff})."
        ),
    );
    let _ = write!(
        o,
        "static inline void motionhdl_isa_ring_dsp(uint16_t base_port, uint16_t message)
{{
    unsigned st = motionhdl_isa_status(base_port);
    unsigned v = (st & {irq_en_bm}) | {p}_MAILBOX_TO_DSP;
    {p}_OUTW({p}_PORT(base_port, {sp}), (uint16_t)v);
    {p}_OUTW({p}_PORT(base_port, {dp}), message);
}}

"
    );
    comment(
        o,
        &format!(
            "Answers the DSP side's doorbell: if STATUS.BELL is set, reads word \
             MOTIONHDL_ISA_MAILBOX_TO_PC into `*message` (the read clears BELL, and with it the \
             IRQ line) and returns 1; else returns 0 and leaves `*message` alone. Keeps IRQ_EN; \
             when it answers, leaves AUTO_INC off and the counter at that word (one IN at {so}; \
             when it answers, one OUT at {so} and one IN at DATA {doff})."
        ),
    );
    let _ = write!(
        o,
        "static inline int motionhdl_isa_take_bell(uint16_t base_port, uint16_t *message)
{{
    unsigned st = motionhdl_isa_status(base_port);
    if (!(st & {bell_bm})) {{
        return 0;
    }}
    unsigned v = (st & {irq_en_bm}) | {p}_MAILBOX_TO_PC;
    {p}_OUTW({p}_PORT(base_port, {sp}), (uint16_t)v);
    *message = (uint16_t){p}_INW({p}_PORT(base_port,
                                                     {dp}));
    return 1;
}}

"
    );
}
