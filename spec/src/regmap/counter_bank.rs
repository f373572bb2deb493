//! The COUNTER block: the counter bank's registers (docs/counter_bank.md).

use super::{field, reg, Access, Block, EnumValue, RegisterArray};

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
/// (see docs/counter_bank.md).
pub fn counter_bank(axes: u32, width: u32) -> Block {
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
    info_err.reset = ERR_COUNT_BITS;
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
    Block {
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
                vec![info_axes, info_width, info_err],
            ),
            reg(
                "SNAPSHOT",
                1,
                WriteOnly,
                "Capture every channel's COUNT, INDEX and STATUS in the same clock.",
                "Any write captures; the data is ignored.",
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
            ],
        }],
    }
}
