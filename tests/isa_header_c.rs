//! `motionhdl_isa.h`, the PC-side C header of the ISA bridge, in gcc/g++:
//! driving a C emulation of the card whose every port access is replayed
//! on the model (`IsaCard`), and compiled as C++11. Under CI a missing
//! compiler fails the test; elsewhere it is reported as skipped.

mod common;

use common::isa::{expected, P};
use common::run;
use motionhdl::isa_header::{isa_header, FILE_NAME};
use motionhdl_model::isa_bridge::{self as card, IsaCard};
use motionhdl_model::regmap::{self, ISA_RAM_WORDS};
use motionhdl_testbench::harness::require_tool;
use std::collections::BTreeMap;
use std::fs;
use std::process::Command;

/// Base switches of the emulated card: base port 0x2a0.
const SWITCHES: u8 = 0xa8;

/// The C test program: an emulation of the card (IsaCard's semantics, with
/// the constants substituted from the model and the map, never from the
/// header), the header on top of it, checks of every number, and the
/// helpers driving the card. Every port access is logged on stdout as
/// `W port value` / `R port value`, and every helper call is announced as
/// `# helper n`, for the replay on `IsaCard`.
fn c_program() -> String {
    let map = regmap::isa_bridge();
    let mut checks = String::new();
    for (name, value) in expected() {
        checks.push_str(&format!("    EQ({name}, {value}ul);\n"));
    }
    for r in &map.registers {
        let port = card::port(SWITCHES, r.offset as u16);
        checks.push_str(&format!(
            "    EQ({P}_PORT(base, {P}_{}_OFFSET), {port}ul);\n",
            r.name
        ));
    }
    checks.push_str(&format!(
        "    EQ(base, {}ul);\n    EQ({P}_BASE_PORT(255), {P}_BASE_PORT_MAX);\n    EQ({P}_BASE_PORT(1), {}ul);\n",
        card::port(SWITCHES, 0),
        card::port(1, 0),
    ));
    let emu = common::isa::emulator_c(SWITCHES);
    let main = format!(
        r##"
static int failures;

#define EQ(a, b)                                                                       \
    do {{                                                                               \
        unsigned long a_ = (unsigned long)(a), b_ = (unsigned long)(b);                \
        if (a_ != b_) {{                                                                \
            printf("FAIL line %d: %s = %lu, want %lu\n", __LINE__, #a, a_, b_);        \
            failures++;                                                                \
        }}                                                                              \
    }} while (0)

static void mark(const char *helper, size_t n)
{{
    printf("# %s %lu\n", helper, (unsigned long)n);
}}

static unsigned status(uint16_t base)
{{
    mark("status", 0);
    return motionhdl_isa_status(base);
}}

static void set_address(uint16_t base, uint16_t addr, int auto_inc)
{{
    mark("set_address", 0);
    motionhdl_isa_set_address(base, addr, auto_inc);
}}

static void clear_address(uint16_t base)
{{
    mark("clear_address", 0);
    motionhdl_isa_clear_address(base);
}}

static void clear_sticky(uint16_t base)
{{
    mark("clear_sticky", 0);
    motionhdl_isa_clear_sticky(base);
}}

static void write_block(uint16_t base, uint16_t start, const uint16_t *src, size_t n)
{{
    mark("write_block", n);
    motionhdl_isa_write_block(base, start, src, n);
}}

static void read_block(uint16_t base, uint16_t start, uint16_t *dst, size_t n)
{{
    mark("read_block", n);
    motionhdl_isa_read_block(base, start, dst, n);
}}

static void enable_irq(uint16_t base, int on)
{{
    mark("enable_irq", 0);
    motionhdl_isa_enable_irq(base, on);
}}

static void ring_dsp(uint16_t base, uint16_t message)
{{
    mark("ring_dsp", 0);
    motionhdl_isa_ring_dsp(base, message);
}}

/* n = 1 when the bell is set, so the log's shape can be checked. */
static int take_bell(uint16_t base, uint16_t *message)
{{
    mark("take_bell", (size_t)emu_bell);
    return motionhdl_isa_take_bell(base, message);
}}

static void dsp_write(uint16_t addr, uint16_t value)
{{
    mark("dsp", 0);
    emu_dsp_write(addr, value);
}}

int main(void)
{{
    static uint16_t src[{P}_RAM_WORDS], dst[{P}_RAM_WORDS];
    const uint16_t base = {P}_BASE_PORT(EMU_SWITCHES);
    const unsigned auto_inc = {P}_STATUS__AUTO_INC_bm;
    const unsigned wrapped = {P}_STATUS__WRAPPED_bm;
    const unsigned collision = {P}_STATUS__COLLISION_bm;
    const unsigned last = {P}_RAM_WORDS - 1u;
    const unsigned irq_en = {P}_STATUS__IRQ_EN_bm;
    const unsigned bell = {P}_STATUS__BELL_bm;
    uint16_t message = 0;
    size_t i;

{checks}
    /* After reset. */
    EQ(status(base), {P}_STATUS_reset);

    /* Addresses, with and without AUTO_INC; addresses wrap modulo the RAM. */
    set_address(base, 5, 0);
    EQ(status(base), 5u);
    set_address(base, (uint16_t)({P}_RAM_WORDS + 7u), 1);
    EQ(status(base), 7u | auto_inc);
    clear_address(base);
    EQ(status(base), auto_inc);

    /* A full block: the counter comes back to 0 and STATUS shows the wrap. */
    for (i = 0; i < {P}_RAM_WORDS; i++) {{
        src[i] = (uint16_t)(i * 0x9e37u + 0x1234u);
    }}
    write_block(base, 0, src, {P}_RAM_WORDS);
    for (i = 0; i < {P}_RAM_WORDS; i++) {{
        EQ(emu_ram[i], src[i]);
    }}
    EQ(status(base), auto_inc | wrapped);
    clear_sticky(base);
    EQ(status(base), auto_inc);
    read_block(base, 0, dst, {P}_RAM_WORDS);
    for (i = 0; i < {P}_RAM_WORDS; i++) {{
        EQ(dst[i], src[i]);
    }}
    EQ(status(base), auto_inc | wrapped);

    /* A block across the end of the RAM. */
    clear_sticky(base);
    write_block(base, (uint16_t)(last - 2u), src + 100, 8);
    EQ(status(base), 5u | auto_inc | wrapped);
    EQ(emu_ram[last], src[102]);
    EQ(emu_ram[0], src[103]);
    read_block(base, (uint16_t)(last - 2u), dst, 8);
    for (i = 0; i < 8; i++) {{
        EQ(dst[i], src[100 + i]);
    }}

    /* Sticky bits: set_address and clear_address keep COLLISION,
       clear_address clears WRAPPED, clear_sticky clears both. */
    emu_collision = 1; /* the DSP port wrote a word a PC write was waiting for */
    set_address(base, 9, 0);
    EQ(status(base), 9u | wrapped | collision);
    clear_address(base);
    EQ(status(base), collision);
    set_address(base, (uint16_t)last, 0);
    mark("raw", 0);
    {P}_INW({P}_PORT(base, {P}_ADDR_INC_OFFSET));
    EQ(status(base), wrapped | collision);
    clear_sticky(base);
    EQ(status(base), 0u);

    /* The other registers, raw: reads of ADDR_CLEAR and ADDR_INC return
       STATUS as it was before their action; writes to them ignore data. */
    mark("raw", 0);
    {P}_OUTW({P}_PORT(base, {P}_STATUS_OFFSET), (uint16_t)(3u | auto_inc));
    EQ({P}_INW({P}_PORT(base, {P}_ADDR_INC_OFFSET)), 3u | auto_inc);
    EQ({P}_INW({P}_PORT(base, {P}_ADDR_CLEAR_OFFSET)), 4u | auto_inc);
    {P}_OUTW({P}_PORT(base, {P}_ADDR_INC_OFFSET), 0xffffu);
    {P}_OUTW({P}_PORT(base, {P}_ADDR_INC_OFFSET), 0xffffu);
    {P}_OUTW({P}_PORT(base, {P}_DATA_OFFSET), 0xbeefu);
    EQ({P}_INW({P}_PORT(base, {P}_DATA_OFFSET)), src[106]); /* word 3, from the wrapped block */
    {P}_OUTW({P}_PORT(base, {P}_ADDR_CLEAR_OFFSET), 0xffffu);
    EQ({P}_INW({P}_PORT(base, {P}_STATUS_OFFSET)), 0u | auto_inc);
    EQ(emu_ram[2], 0xbeefu);
    EQ(emu_misses, 0u);
    /* Another card's port: not answered. */
    EQ({P}_INW({P}_PORT(base, {P}_PORT_COUNT)), 0xffffu);
    EQ(emu_misses, 1u);

    /* The doorbells. The DSP rings: BELL, and IRQ once enabled. */
    dsp_write({P}_MAILBOX_TO_PC, 0x1234u);
    EQ(status(base) & bell, bell);
    EQ(emu_irq(), 0);
    enable_irq(base, 1);
    EQ(emu_irq(), 1);
    EQ(status(base), auto_inc | irq_en | bell);
    EQ(take_bell(base, &message), 1);
    EQ(message, 0x1234u);
    EQ(emu_irq(), 0);
    EQ(status(base), {P}_MAILBOX_TO_PC | irq_en);
    EQ(take_bell(base, &message), 0);
    /* The PC rings. The full-RAM block above wrote the DSP's mailbox
       too, so its bell is up already: the DSP takes it first. */
    EQ(emu_dsp_bell, 1);
    emu_dsp_bell = 0;
    ring_dsp(base, 0x55aau);
    EQ(emu_dsp_bell, 1);
    EQ(emu_ram[{P}_MAILBOX_TO_DSP], 0x55aau);
    EQ(status(base), {P}_MAILBOX_TO_DSP | irq_en);
    /* The address helpers keep IRQ_EN; clear_sticky answers the bell. */
    set_address(base, 3, 1);
    EQ(status(base), 3u | auto_inc | irq_en);
    dsp_write({P}_MAILBOX_TO_PC, 7u);
    clear_address(base);
    EQ(status(base), auto_inc | irq_en | bell);
    clear_sticky(base);
    EQ(status(base), auto_inc | irq_en);
    EQ(emu_irq(), 0);
    enable_irq(base, 0);
    EQ(status(base), auto_inc);

    printf("DONE %d\n", failures);
    return failures == 0 ? 0 : 1;
}}
"##
    );
    emu + &main
}

/// One logged port access.
#[derive(Debug)]
enum Access {
    Write(u16, u16),
    Read(u16, u16),
    /// A DSP-side write: word address, value.
    Dsp(u16, u16),
}

impl Access {
    fn port(&self) -> u16 {
        match self {
            Access::Write(p, _) | Access::Read(p, _) => *p,
            Access::Dsp(..) => panic!("a DSP write has no port"),
        }
    }
}

/// The program's log as (helper, n, accesses) segments.
fn segments(out: &str) -> Vec<(String, usize, Vec<Access>)> {
    let mut segs: Vec<(String, usize, Vec<Access>)> = vec![("start".into(), 0, Vec::new())];
    for l in out.lines() {
        let w: Vec<&str> = l.split(' ').collect();
        match w[..] {
            ["#", helper, n] => segs.push((helper.to_string(), n.parse().unwrap(), Vec::new())),
            ["W", p, v] => segs
                .last_mut()
                .unwrap()
                .2
                .push(Access::Write(p.parse().unwrap(), v.parse().unwrap())),
            ["R", p, v] => segs
                .last_mut()
                .unwrap()
                .2
                .push(Access::Read(p.parse().unwrap(), v.parse().unwrap())),
            ["D", a, v] => segs
                .last_mut()
                .unwrap()
                .2
                .push(Access::Dsp(a.parse().unwrap(), v.parse().unwrap())),
            _ => {}
        }
    }
    segs
}

/// Replays every access on the model and checks each helper's accesses
/// against what the header says it does.
fn check_log(out: &str) {
    let map = regmap::isa_bridge();
    let base = card::port(SWITCHES, 0);
    let data = base + map.register("DATA").offset as u16;
    let status = base + map.register("STATUS").offset as u16;
    let collision = card::status::COLLISION;
    let mut model = IsaCard::new(SWITCHES);
    let mut helpers = BTreeMap::new();
    let segs = segments(out);
    for (helper, n, accesses) in &segs {
        for a in accesses {
            match *a {
                Access::Write(p, v) => {
                    model.io_write(p, false, v);
                }
                Access::Read(p, v) => {
                    let want = model.io_read(p, false).unwrap_or(u16::MAX);
                    // IsaCard has no DSP port, so its STATUS never shows COLLISION.
                    let returns_status = card::selected(p, false, SWITCHES) && p != data;
                    let got = if returns_status { v & !collision } else { v };
                    assert_eq!(got, want, "read of port {p:#x} in {helper}");
                }
                Access::Dsp(a, v) => {
                    assert_eq!(helper, "dsp", "a DSP write inside {helper}");
                    model.dsp_write(a, v);
                }
            }
        }
        if helper == "raw" || helper == "start" || helper == "dsp" {
            continue;
        }
        *helpers.entry(helper.clone()).or_insert(0) += 1;
        let shape: Vec<String> = accesses
            .iter()
            .map(|a| {
                let reg = if a.port() == data {
                    "DATA"
                } else if a.port() == status {
                    "STATUS"
                } else {
                    panic!("{helper} accessed port {:#x}: {accesses:?}", a.port())
                };
                match a {
                    Access::Write(..) => format!("OUT {reg}"),
                    Access::Read(..) => format!("IN {reg}"),
                    Access::Dsp(..) => unreachable!("DSP writes are in dsp segments"),
                }
            })
            .collect();
        let mut want: Vec<&str> = match helper.as_str() {
            "status" => vec!["IN STATUS"],
            "set_address" | "clear_address" | "clear_sticky" | "enable_irq" | "write_block"
            | "read_block" => vec!["IN STATUS", "OUT STATUS"],
            "ring_dsp" => vec!["IN STATUS", "OUT STATUS", "OUT DATA"],
            "take_bell" if *n == 1 => vec!["IN STATUS", "OUT STATUS", "IN DATA"],
            "take_bell" => vec!["IN STATUS"],
            other => panic!("unknown helper {other}"),
        };
        match helper.as_str() {
            "write_block" => want.extend(std::iter::repeat_n("OUT DATA", *n)),
            "read_block" => want.extend(std::iter::repeat_n("IN DATA", *n)),
            _ => {}
        }
        assert_eq!(shape, want, "{helper} {n}");
    }
    for h in [
        "status",
        "set_address",
        "clear_address",
        "clear_sticky",
        "write_block",
        "read_block",
        "enable_irq",
        "ring_dsp",
        "take_bell",
    ] {
        assert!(helpers.contains_key(h), "{h} never called");
    }
    assert!(
        segs.iter()
            .any(|s| s.0 == "write_block" && s.1 == ISA_RAM_WORDS as usize),
        "no full-RAM block"
    );
}

#[test]
fn header_drives_an_emulated_card_in_c99_and_c11() {
    if require_tool("gcc").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join(FILE_NAME), isa_header()).unwrap();
    let src = dir.path().join("t.c");
    fs::write(&src, c_program()).unwrap();
    for std in ["-std=c99", "-std=c11"] {
        // Port I/O through the user's macros, then through the functions
        // the header declares when the macros are not defined.
        for mode in [None, Some("-DUSE_FUNCTIONS")] {
            let what = format!("{std} {}", mode.unwrap_or("(macros)"));
            let exe = dir.path().join("t");
            let (ok, out, err) = run(Command::new("gcc")
                .args([std, "-Wall", "-Wextra", "-Werror", "-pedantic"])
                .args(mode)
                .arg("-I")
                .arg(dir.path())
                .arg("-o")
                .arg(&exe)
                .arg(&src));
            assert!(ok && err.is_empty(), "{what}: gcc:\n{out}{err}");
            let (ok, out, err) = run(&mut Command::new(&exe));
            let fails: Vec<&str> = out.lines().filter(|l| l.starts_with("FAIL")).collect();
            assert!(
                ok,
                "{what}: the C test failed:\n{}\n{err}",
                fails.join("\n")
            );
            assert!(fails.is_empty() && out.ends_with("DONE 0\n"), "{what}");
            check_log(&out);
        }
    }

    // Only one of the two port macros: a clear #error.
    let half = dir.path().join("half.c");
    fs::write(
        &half,
        format!(
            "#define MOTIONHDL_ISA_INW(port) 0u\n#include \"{FILE_NAME}\"\nint main(void) {{ return 0; }}\n"
        ),
    )
    .unwrap();
    let (ok, _, err) = run(Command::new("gcc")
        .args(["-std=c99", "-fsyntax-only", "-I"])
        .arg(dir.path())
        .arg(&half));
    assert!(!ok && err.contains("define both"), "{err}");
}

#[test]
fn header_compiles_as_cpp11() {
    if require_tool("g++").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join(FILE_NAME), isa_header()).unwrap();
    let src = dir.path().join("t.cpp");
    fs::write(
        &src,
        format!("#include \"{FILE_NAME}\"\n#include \"{FILE_NAME}\"\nint main() {{ return 0; }}\n"),
    )
    .unwrap();
    let (ok, out, err) = run(Command::new("g++")
        .args([
            "-std=c++11",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-fsyntax-only",
            "-I",
        ])
        .arg(dir.path())
        .arg(&src));
    assert!(ok && err.is_empty(), "g++ -std=c++11:\n{out}{err}");
}
