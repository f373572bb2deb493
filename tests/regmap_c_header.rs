//! `motionhdl_regs.h`, the MCU's C header of the register map: every
//! number it defines against the table, its layout and comments, and the
//! header in g++. A test that needs g++ fails under CI when it is missing;
//! elsewhere it is skipped.

mod common;

use common::regmap::{check_header_numbers, default_map, other_configs};
use common::run;
use motionhdl::regmap_export::c_header;
use motionhdl_model::regmap::mcu_map;
use motionhdl_testbench::harness::require_tool;
use std::fs;
use std::process::Command;

#[test]
fn header_defines_every_number_of_the_table() {
    let map = default_map();
    let n = check_header_numbers(&map);
    // 4 globals and 5 FSMC settings; ID: 2 + 10 registers x 2 + 14 fields x 4 + 2 enum values;
    // COUNTER: 2 + 3 x 2 + 8 fields x 4, CH: 2 + 6 x 2 + 24 fields x 4 +
    // 5 enum values; PULSE: 2 + 2 x 2 + 3 fields x 4, AX: 2 + 16 x 2 +
    // 26 fields x 4 + 2 enum values; SAFETY: 2 + 37 x 2 + 64 fields x 4
    // + 2 enum values; SHARED_RAM: 4.
    assert_eq!(
        n,
        4 + 5
            + (2 + 20 + 56 + 2)
            + (2 + 6 + 32)
            + (2 + 12 + 96 + 5)
            + (2 + 4 + 12)
            + (2 + 32 + 104 + 2)
            + (2 + 74 + 256 + 2)
            + 4
    );
    assert_eq!(n, 740);
    for c in other_configs() {
        check_header_numbers(&mcu_map(&c));
    }

    let h = c_header::header(&map);
    for want in [
        "#ifndef MOTIONHDL_REGS_H\n#define MOTIONHDL_REGS_H\n",
        "#include <stdint.h>",
        "#ifdef __cplusplus\nextern \"C\" {\n#endif",
        "#ifndef __I\n",
        "#define __I volatile const\n",
        "#ifndef __O\n#define __O volatile\n#endif",
        "#ifndef __IO\n#define __IO volatile\n#endif",
        "#define MOTIONHDL_FSMC_NE1_BASE 0x60000000u",
        "STM32F4 FSMC bank 1, region 1",
        "#define MOTIONHDL_COUNTER_CH_OFFSET(n) (0x0020u + (uint32_t)(n) * MOTIONHDL_COUNTER_CH_STRIDE)",
        "    __IO uint16_t SHARED_RAM[MOTIONHDL_SHARED_RAM_WORDS]; /* 0x1000 */",
        "} MOTIONHDL_COUNTER_CH_TypeDef;",
        "} MOTIONHDL_COUNTER_TypeDef;",
        "} MOTIONHDL_ID_TypeDef;",
        "} MOTIONHDL_TypeDef;",
        "    MOTIONHDL_COUNTER_CH_TypeDef CH[MOTIONHDL_COUNTER_CH_NUM]; /* +0x020 */",
        // Every byte of the 8 KB window: the RAM's mirror ends it.
        "    __IO uint16_t SHARED_RAM_MIRROR[1024]; /* 0x1800 */",
        "#define MOTIONHDL(base) ((MOTIONHDL_TypeDef *)(uintptr_t)(base))",
        "    __O  uint32_t SNAPSHOT;",
        "    __I  uint32_t COUNT;",
        "    __IO uint32_t CTRL;",
    ] {
        assert!(h.contains(want), "header lacks `{want}`");
    }
    assert!(h.ends_with("#endif /* MOTIONHDL_REGS_H */\n"));
    // Descriptions, side effects and access notes reach the comments.
    let counter = map.block("COUNTER");
    let cmd = counter.array("CH").register("CMD");
    assert!(h.contains("CH[n].CMD (CH[n] +0x04), write-only: "));
    let flat = h.replace("\n * ", " ");
    assert!(flat.contains(cmd.side_effects), "side effects of CMD");
    assert!(flat.contains(counter.register("SNAPSHOT").side_effects));
    assert!(flat.contains("Write-only: reads return 0."));
    assert!(flat.contains("Access registers only as 32-bit words, never as halfwords or bytes."));
    for r in &counter.array("CH").registers {
        assert!(flat.contains(r.description), "{}", r.name);
    }
}

#[test]
fn header_compiles_as_cpp11() {
    if require_tool("g++").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    fs::write(
        dir.path().join(c_header::FILE_NAME),
        c_header::header(&default_map()),
    )
    .unwrap();
    let src = dir.path().join("t.cpp");
    fs::write(
        &src,
        "#include \"motionhdl_regs.h\"\n#include \"motionhdl_regs.h\"\n\
         static_assert(sizeof(MOTIONHDL_COUNTER_CH_TypeDef) == MOTIONHDL_COUNTER_CH_STRIDE, \"stride\");\n\
         int main() {\n\
         volatile MOTIONHDL_TypeDef *w = MOTIONHDL(MOTIONHDL_FSMC_NE1_BASE);\n\
         (void)w;\n\
         return 0;\n}\n",
    )
    .unwrap();
    for std in ["-std=c++11", "-std=c++17"] {
        let (ok, out, err) = run(Command::new("g++")
            .args([
                std,
                "-Wall",
                "-Wextra",
                "-Werror",
                "-pedantic",
                "-fsyntax-only",
                "-I",
            ])
            .arg(dir.path())
            .arg(&src));
        assert!(ok && err.is_empty(), "g++ {std}:\n{out}{err}");
    }
}
