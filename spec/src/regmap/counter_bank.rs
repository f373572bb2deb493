//! The COUNTER block: the counter bank's registers (docs/counter_bank.md).

use super::{field, reg, Access, Block, EnumValue, Field, RegisterArray};
use crate::CounterFeatures;

/// Counting modes of CTRL.MODE.
pub mod mode {
    pub const X4: u32 = 0;
    pub const X2: u32 = 1;
    pub const X1: u32 = 2;
    pub const PULSE_DIR: u32 = 3;
    pub const CW_CCW: u32 = 4;
}

/// Width of the per-channel error counter in the gateware.
pub const ERR_COUNT_BITS: u32 = 8;

/// The counter bank's registers for `axes` channels of `width`-bit counters
/// with every feature (see docs/counter_bank.md).
pub fn counter_bank(axes: u32, width: u32) -> Block {
    counter_bank_with(axes, width, CounterFeatures::ALL)
}

/// Bit of INFO where the feature flags start, in [`CounterFeatures::KEYS`] order.
const INFO_FEATURES_LSB: u32 = 24;

/// The counter bank's registers for a build with `features`: a feature left
/// out has no fields or registers here, so every export and both twins
/// follow from this one table.
pub fn counter_bank_with(axes: u32, width: u32, features: CounterFeatures) -> Block {
    use Access::*;
    assert!(
        (1..=16).contains(&axes),
        "axes = {axes} out of range 1..=16"
    );
    assert!(
        (2..=32).contains(&width),
        "width = {width} out of range 2..=32"
    );
    let mut info_axes = field("AXES", 0, 5, ReadOnly, "Number of channels.");
    info_axes.reset = axes;
    let mut info_width = field("WIDTH", 8, 6, ReadOnly, "Counter width in bits.");
    info_width.reset = width;
    let mut info_err = field(
        "ERR_BITS",
        16,
        4,
        ReadOnly,
        "Width of each channel's error counter.",
    );
    info_err.reset = if features.error { ERR_COUNT_BITS } else { 0 };
    let mut info = vec![info_axes, info_width, info_err];
    for (i, (name, description)) in [
        (
            "FILTER",
            "1: the build has the input filters (CTRL.FILTER_AB, FILTER_Z).",
        ),
        (
            "INDEX",
            "1: the build has the index logic (INDEX, CTRL.IDX_*, CMD.ARM).",
        ),
        (
            "ERROR",
            "1: the build detects illegal transitions (STATUS.ERR, ERR_COUNT).",
        ),
        (
            "SNAPSHOT",
            "1: COUNT, INDEX and STATUS read as SNAPSHOT captured them; 0: live.",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let mut f = field(name, INFO_FEATURES_LSB + i as u32, 1, ReadOnly, description);
        f.reset = (features.bits() >> i) & 1;
        info.push(f);
    }
    let mut mode = field("MODE", 0, 3, ReadWrite, "Counting mode.");
    mode.values = vec![
        EnumValue {
            name: "X4",
            value: mode::X4,
            description: "Quadrature, every edge of A and B.",
        },
        EnumValue {
            name: "X2",
            value: mode::X2,
            description: "Quadrature, every edge of A.",
        },
        EnumValue {
            name: "X1",
            value: mode::X1,
            description: "Quadrature, one count per A cycle.",
        },
        EnumValue {
            name: "PULSE_DIR",
            value: mode::PULSE_DIR,
            description: "A = pulse (rising edge), B = direction (1 = down).",
        },
        EnumValue {
            name: "CW_CCW",
            value: mode::CW_CCW,
            description: "A pulses count up, B pulses count down.",
        },
    ];
    let block = Block {
        name: "COUNTER",
        description: "Quadrature/pulse counter bank",
        base: 0,
        address_bits: 8,
        registers: vec![
            reg(
                "INFO",
                0,
                ReadOnly,
                "Build parameters of the bank.",
                "",
                info,
            ),
            reg(
                "SNAPSHOT",
                1,
                WriteOnly,
                if features.snapshot {
                    "Capture every channel's COUNT, INDEX and STATUS in the same clock."
                } else {
                    "No counter snapshot in this build: COUNT, INDEX and STATUS read live."
                },
                if features.snapshot {
                    "Any write captures; the data is ignored. On the MCU bus it also captures every pulse generator's POSITION."
                } else {
                    "The counters ignore a write. On the MCU bus it captures every pulse generator's POSITION."
                },
                vec![],
            ),
            reg(
                "PRESET",
                2,
                ReadWrite,
                "Value a channel's CMD.LOAD copies into its counter. Reads sign-extended.",
                "",
                vec![field(
                    "VALUE",
                    0,
                    32,
                    ReadWrite,
                    "Preset value, taken modulo 2^WIDTH.",
                )],
            ),
        ],
        arrays: vec![RegisterArray {
            name: "CH",
            count: axes,
            offset: 8,
            stride: 8,
            registers: vec![
                reg(
                    "CTRL",
                    0,
                    ReadWrite,
                    "Channel configuration.",
                    "",
                    vec![
                        mode,
                        field("REVERSE", 3, 1, ReadWrite, "Swap up and down."),
                        field(
                            "ERR_EN",
                            4,
                            1,
                            ReadWrite,
                            "Latch illegal quadrature transitions into STATUS.ERR and ERR_COUNT.",
                        ),
                        field("IDX_INVERT", 5, 1, ReadWrite, "Index is active low."),
                        field(
                            "IDX_LATCH",
                            6,
                            1,
                            ReadWrite,
                            "Latch the count into INDEX on an index event.",
                        ),
                        field(
                            "IDX_CLEAR",
                            7,
                            1,
                            ReadWrite,
                            "Clear the count on an index event.",
                        ),
                        field(
                            "IDX_GATE",
                            8,
                            1,
                            ReadWrite,
                            "Accept the index only while A and B are both high.",
                        ),
                        field(
                            "IDX_ONESHOT",
                            9,
                            1,
                            ReadWrite,
                            "Index actions only while STATUS.ARMED; the first event disarms.",
                        ),
                        field(
                            "FILTER_AB",
                            16,
                            4,
                            ReadWrite,
                            "A/B filter: a level is accepted after FILTER_AB+1 equal samples.",
                        ),
                        field("FILTER_Z", 20, 4, ReadWrite, "Index filter, as FILTER_AB."),
                    ],
                ),
                reg(
                    "CMD",
                    1,
                    WriteOnly,
                    "Channel commands; write 1 to a bit to act.",
                    "CLEAR wins over LOAD, both over an index clear and counting in that clock.",
                    vec![
                        field("CLEAR", 0, 1, WriteOnly, "Set the count to 0."),
                        field("LOAD", 1, 1, WriteOnly, "Set the count to PRESET."),
                        field("ARM", 2, 1, WriteOnly, "Arm the one-shot index."),
                        field(
                            "CLEAR_STATUS",
                            3,
                            1,
                            WriteOnly,
                            "Clear STATUS.ERR, ERR_COUNT and SEEN.",
                        ),
                    ],
                ),
                reg(
                    "COUNT",
                    2,
                    ReadOnly,
                    "Count at the last SNAPSHOT, sign-extended from WIDTH bits.",
                    "",
                    vec![field(
                        "VALUE",
                        0,
                        32,
                        ReadOnly,
                        "Two's complement count; wraps modulo 2^WIDTH.",
                    )],
                ),
                reg(
                    "INDEX",
                    3,
                    ReadOnly,
                    "Index latch at the last SNAPSHOT, sign-extended from WIDTH bits.",
                    "",
                    vec![field(
                        "VALUE",
                        0,
                        32,
                        ReadOnly,
                        "Count captured at the last latching index event.",
                    )],
                ),
                reg(
                    "STATUS",
                    4,
                    ReadOnly,
                    "Status at the last SNAPSHOT.",
                    "",
                    vec![
                        field(
                            "ERR",
                            0,
                            1,
                            ReadOnly,
                            "Sticky: an illegal quadrature transition was seen.",
                        ),
                        field("ARMED", 1, 1, ReadOnly, "One-shot index armed."),
                        field("SEEN", 2, 1, ReadOnly, "Sticky: an index event was seen."),
                        field("A", 4, 1, ReadOnly, "Accepted level of A."),
                        field("B", 5, 1, ReadOnly, "Accepted level of B."),
                        field(
                            "Z",
                            6,
                            1,
                            ReadOnly,
                            "Accepted level of Z (before IDX_INVERT).",
                        ),
                        field(
                            "ERR_COUNT",
                            8,
                            ERR_COUNT_BITS,
                            ReadOnly,
                            "Illegal transitions seen, saturating.",
                        ),
                    ],
                ),
                reg(
                    "HOME_COUNT",
                    5,
                    ReadOnly,
                    "The count in the clock where the same-numbered axis's HOME input turned active, sign-extended from WIDTH bits.",
                    "Live, not through SNAPSHOT: it changes only at a home event (the bank's `home` input; on the MCU top the safety block's, the edge where it sets HOME_ALARM_CAUSE.HOME). 0 after reset, and always where nothing drives `home` (the ISA-only builds).",
                    vec![field(
                        "VALUE",
                        0,
                        32,
                        ReadOnly,
                        "Two's complement count; wraps modulo 2^WIDTH.",
                    )],
                ),
            ],
        }],
    };
    without_absent(block, features)
}

/// Whether a channel field exists in a build with `features`.
fn channel_field_kept(register: &str, field: &str, f: CounterFeatures) -> bool {
    match (register, field) {
        ("CTRL", "FILTER_AB") => f.filter,
        ("CTRL", "FILTER_Z") => f.filter && f.index,
        ("CTRL", "ERR_EN") | ("STATUS", "ERR" | "ERR_COUNT") => f.error,
        ("CTRL", name) if name.starts_with("IDX_") => f.index,
        ("CMD", "ARM") | ("STATUS", "ARMED" | "SEEN" | "Z") => f.index,
        ("CMD", "CLEAR_STATUS") => f.error || f.index,
        _ => true,
    }
}

/// Removes what a build without some features lacks and words the rest for it.
fn without_absent(mut block: Block, f: CounterFeatures) -> Block {
    let ch = &mut block.arrays[0];
    ch.registers.retain(|r| r.name != "INDEX" || f.index);
    for r in &mut ch.registers {
        let name = r.name;
        r.fields
            .retain(|x: &Field| channel_field_kept(name, x.name, f));
        if !f.snapshot {
            r.description = match name {
                "COUNT" => "Live count, sign-extended from WIDTH bits (no SNAPSHOT in this build).",
                "INDEX" => {
                    "Live index latch, sign-extended from WIDTH bits (no SNAPSHOT in this build)."
                }
                "STATUS" => "Live status (no SNAPSHOT in this build).",
                _ => r.description,
            };
        }
        for x in &mut r.fields {
            if (name, x.name) == ("CMD", "CLEAR_STATUS") {
                x.description = match (f.error, f.index) {
                    (true, true) => "Clear STATUS.ERR, ERR_COUNT and SEEN.",
                    (true, false) => "Clear STATUS.ERR and ERR_COUNT.",
                    _ => "Clear STATUS.SEEN.",
                };
            }
        }
    }
    block
}
