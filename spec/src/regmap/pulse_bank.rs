//! The PULSE block: the pulse generators' registers
//! (docs/pulse_generator.md).

use super::{field, reg, Access, Block, EnumValue, RegisterArray};

/// The pulse generators: per axis an NCO rate, step timing, output mode
/// and the position of emitted steps; RUN starts and stops axes together.
pub fn pulse_bank(axes: u32, width: u32) -> Block {
    use Access::*;
    assert!(
        (1..=16).contains(&axes),
        "axes = {axes} out of range 1..=16"
    );
    assert!(
        (2..=32).contains(&width),
        "width = {width} out of range 2..=32"
    );
    let mut info_axes = field("AXES", 0, 5, ReadOnly, "Number of pulse generators.");
    info_axes.reset = axes;
    let mut info_width = field("WIDTH", 8, 6, ReadOnly, "POSITION width in bits.");
    info_width.reset = width;
    let mut mode = field(
        "MODE",
        0,
        1,
        ReadWrite,
        "Output mode: the pulse-mode selector's K input.",
    );
    mode.values = vec![
        EnumValue {
            name: "PULSE_DIR",
            value: 0,
            description: "F1 = step (S1), F2 = direction (S2, 1 = negative).",
        },
        EnumValue {
            name: "CW_CCW",
            value: 1,
            description:
                "F1 = steps in the positive direction, F2 = steps in the negative direction.",
        },
    ];
    let timing = |lo: &'static str, hi: &'static str, lo_doc, hi_doc| {
        vec![
            field(lo, 0, 16, ReadWrite, lo_doc),
            field(hi, 16, 16, ReadWrite, hi_doc),
        ]
    };
    Block {
        name: "PULSE",
        description: "Step/pulse generators (docs/pulse_generator.md)",
        base: 0,
        address_bits: 9,
        registers: vec![
            reg("INFO", 0, ReadOnly, "Build parameters of the pulse generators.", "", vec![info_axes, info_width]),
            reg(
                "RUN",
                1,
                ReadWrite,
                "Bit n runs axis n's NCO. One write starts (or stops) every axis it names in the same clock.",
                "Stopping an axis stops new steps; steps already commanded still go out.",
                vec![field("AXES", 0, axes, ReadWrite, "One bit per axis.")],
            ),
        ],
        arrays: vec![RegisterArray {
            name: "AX",
            count: axes,
            offset: 16,
            stride: 16,
            registers: vec![
                reg(
                    "CTRL",
                    0,
                    ReadWrite,
                    "Output mode.",
                    "",
                    vec![
                        mode,
                        field(
                            "QUADRATURE",
                            1,
                            1,
                            ReadWrite,
                            "F1/F2 = quadrature A/B instead of the selector: one A or B edge per step (count it x4).",
                        ),
                        field(
                            "MOVES",
                            2,
                            1,
                            ReadWrite,
                            "The NCO runs the segment FIFO's moves instead of RATE.",
                        ),
                    ],
                ),
                reg(
                    "RATE",
                    1,
                    ReadWrite,
                    "Signed NCO rate: steps per clock = RATE / 2^32, up to half the clock.",
                    "",
                    vec![field("VALUE", 0, 32, ReadWrite, "Two's complement; the sign is the direction.")],
                ),
                reg(
                    "STEP_TIMING",
                    2,
                    ReadWrite,
                    "Minimum step pulse length and space, in clocks (0 counts as 1); acts one clock after it is written.",
                    "",
                    timing("STEP_LEN", "STEP_SPACE", "S1 high at least this long.", "S1 low at least this long between steps."),
                ),
                reg(
                    "DIR_TIMING",
                    3,
                    ReadWrite,
                    "Minimum direction set-up and hold, in clocks (0 counts as 1); acts one clock after it is written.",
                    "",
                    timing("DIR_SETUP", "DIR_HOLD", "S2 stable at least this long before S1 rises.", "S1 low at least this long before S2 changes."),
                ),
                reg(
                    "POSITION",
                    4,
                    ReadOnly,
                    "Steps emitted at the counter bank's last SNAPSHOT, sign-extended from WIDTH bits.",
                    "",
                    vec![field("VALUE", 0, 32, ReadOnly, "Two's complement; wraps modulo 2^WIDTH.")],
                ),
                reg(
                    "STATUS",
                    5,
                    ReadOnly,
                    "Live state of the axis.",
                    "",
                    vec![
                        field("PENDING", 0, 16, ReadOnly, "Steps queued, signed: a step enters 2 clocks after the NCO commands it and leaves the clock after S1 rises."),
                        field("BUSY", 16, 1, ReadOnly, "A commanded step is not yet out (entering, queued or leaving) or S1 is high."),
                        field("MOVING", 17, 1, ReadOnly, "A segment is running."),
                        field(
                            "DONE",
                            18,
                            1,
                            ReadOnly,
                            "Sticky: every pushed segment has commanded all its steps (cleared by SEG_PUSH). DONE and not BUSY: the move is out.",
                        ),
                        field(
                            "OVERFLOW",
                            19,
                            1,
                            ReadOnly,
                            "Sticky: a SEG_PUSH found the FIFO full and was dropped (cleared by writing CTRL).",
                        ),
                        field("FIFO_LEVEL", 20, 7, ReadOnly, "Segments pushed and not yet loaded (0..=64)."),
                        field("FIFO_LOW", 27, 1, ReadOnly, "FIFO_LEVEL <= FIFO_LOW_WATER.LEVEL: time to refill."),
                        field(
                            "BRAKING",
                            28,
                            1,
                            ReadOnly,
                            "A decelerating stop is under way: the NCO's rate falls by DECEL each clock it advances, RUN stays 0, until the rate reaches 0.",
                        ),
                    ],
                ),
                reg(
                    "SEG_STEPS",
                    6,
                    WriteOnly,
                    "Next segment: steps to command (unsigned).",
                    "Written straight into the FIFO's free tail slot (block RAM); dropped while the FIFO is full (write a segment while FIFO_LEVEL < 64). Write all four SEG_* before each SEG_PUSH: a field not written keeps the slot's old contents, across resets too.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Steps.")],
                ),
                reg(
                    "SEG_RATE",
                    7,
                    WriteOnly,
                    "Next segment: starting NCO rate (signed, as RATE).",
                    "Written straight into the FIFO's free tail slot (block RAM); dropped while the FIFO is full (write a segment while FIFO_LEVEL < 64). Write all four SEG_* before each SEG_PUSH: a field not written keeps the slot's old contents, across resets too.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Two's complement; the sign is the direction.")],
                ),
                reg(
                    "SEG_ACCEL",
                    8,
                    WriteOnly,
                    "Next segment: added to the rate on every clock the NCO advances (signed, 16 fraction bits: one LSB is 2^-16 of a RATE LSB per clock).",
                    "Written straight into the FIFO's free tail slot (block RAM); dropped while the FIFO is full (write a segment while FIFO_LEVEL < 64). Write all four SEG_* before each SEG_PUSH: a field not written keeps the slot's old contents, across resets too.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Two's complement; 2^-48 steps/clock^2 per LSB.")],
                ),
                reg(
                    "SEG_PUSH",
                    9,
                    WriteOnly,
                    "Push {SEG_STEPS, SEG_RATE, SEG_ACCEL, SEG_JERK} into the axis's segment FIFO (64 deep, besides the segment running).",
                    "Any write pushes; the data is ignored. A push into a full FIFO is dropped and sets STATUS.OVERFLOW. The segment can load 4 clocks after it reaches the FIFO's head.",
                    vec![],
                ),
                reg(
                    "FIFO_LOW_WATER",
                    10,
                    ReadWrite,
                    "STATUS.FIFO_LOW is set while FIFO_LEVEL is at most LEVEL.",
                    "",
                    vec![field("LEVEL", 0, 7, ReadWrite, "Low-water mark in segments (0..=64; 0: FIFO_LOW means empty).")],
                ),
                reg(
                    "SEG_JERK",
                    11,
                    WriteOnly,
                    "Next segment: added to the acceleration on every clock the NCO advances (signed, 16 fraction bits: one LSB is 2^-16 of a SEG_ACCEL LSB per clock).",
                    "Written straight into the tail entry of the jerk ring (block RAM, 128 entries: the FIFO's depth twice); dropped while the FIFO is full. Write all four SEG_* before each SEG_PUSH: a jerk not written is the one written 128 pushes before, across resets too.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Two's complement; 2^-64 steps/clock^3 per LSB (0: the acceleration stays SEG_ACCEL).")],
                ),
                reg(
                    "HOME_POSITION",
                    12,
                    ReadOnly,
                    "POSITION (the steps emitted) in the clock where the axis's HOME input turned active, sign-extended from WIDTH bits.",
                    "Live, not through SNAPSHOT: it changes only at a home event, the edge where the safety block sets HOME_ALARM_CAUSE.HOME (an enabled HOME input turning active after its filter). 0 after reset.",
                    vec![field("VALUE", 0, 32, ReadOnly, "Two's complement; wraps modulo 2^WIDTH.")],
                ),
                reg(
                    "SOFT_MIN",
                    13,
                    ReadWrite,
                    "Soft limit: the lowest POSITION the axis may reach (two's complement, WIDTH bits stored, read sign-extended).",
                    "0 after reset. SAFETY.SOFT_LIMIT_CTRL.MIN turns it on; the comparison POSITION <= SOFT_MIN is a flip-flop, one edge after POSITION.",
                    vec![field("VALUE", 0, 32, ReadWrite, "Two's complement; taken modulo 2^WIDTH.")],
                ),
                reg(
                    "SOFT_MAX",
                    14,
                    ReadWrite,
                    "Soft limit: the highest POSITION the axis may reach (two's complement, WIDTH bits stored, read sign-extended).",
                    "0 after reset. SAFETY.SOFT_LIMIT_CTRL.MAX turns it on; the comparison POSITION >= SOFT_MAX is a flip-flop, one edge after POSITION.",
                    vec![field("VALUE", 0, 32, ReadWrite, "Two's complement; taken modulo 2^WIDTH.")],
                ),
                reg(
                    "DECEL",
                    15,
                    ReadWrite,
                    "Deceleration of a direction stop (a limit, an alarm, a soft limit or HOME_STOP): 0 stops at once; otherwise the axis brakes from the rate it runs at, by VALUE each clock the NCO advances, to rate 0.",
                    "0 after reset. A stop brakes only when the axis's NCO rate heads into it; otherwise (and always on HALT) it is instant. While braking STATUS.BRAKING is set; from rate R the NCO commands at most R^2 / (2^17 x VALUE) + 2 steps after the stop, besides those already queued (PENDING).",
                    vec![field("VALUE", 0, 31, ReadWrite, "Unsigned, in SEG_ACCEL's unit: 2^-48 steps/clock^2 (0: instant stop).")],
                ),
            ],
        }],
    }
}

// The SEG_*, FIFO_LEVEL and FIFO_LOW_WATER descriptions above say how deep
// the FIFO is.
const _: () = assert!(crate::pulse::SEGMENT_FIFO_DEPTH == 64);
