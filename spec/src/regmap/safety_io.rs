//! The SAFETY block: e-stop, watchdog, drive enables and the interrupt
//! line's causes and masks (docs/safety_io.md).

use super::{field, reg, with_reset, Access, Block, EnumValue, Field};
use crate::safety_io::{GPIO_INPUTS, GPIO_OUTPUTS, WATCHDOG_KEY};

/// One bit per axis, `access`, with `description`.
fn axes_field(axes: u32, access: Access, description: &'static str) -> Vec<Field> {
    vec![field("AXES", 0, axes, access, description)]
}

/// The safety and I/O block of `axes` axes (1..=16).
pub fn safety_io(axes: u32) -> Block {
    use Access::*;
    assert!(
        (1..=16).contains(&axes),
        "axes = {axes} out of range 1..=16"
    );
    let system_causes = |access: Access| {
        vec![
            field("ESTOP", 0, 1, access, "The e-stop latch was set."),
            field("WATCHDOG", 1, 1, access, "The watchdog has bitten."),
            field(
                "DOORBELL",
                2,
                1,
                access,
                "The PC wrote the DSP side's mailbox word of the shared RAM (ISA_MAILBOX_TO_DSP).",
            ),
            field(
                "SERVO_TICK",
                3,
                1,
                access,
                "A servo tick (SERVO.TICK_PERIOD): the counters' snapshot was taken and the staged DAC codes started out. Never set in a build without the SERVO block.",
            ),
        ]
    };
    let mut polarity = field(
        "ACTIVE_HIGH",
        0,
        1,
        ReadWrite,
        "IRQ pin polarity: 0 = active low (open-drain style, the reset value), 1 = active high.",
    );
    polarity.values = vec![
        EnumValue {
            name: "ACTIVE_LOW",
            value: 0,
            description: "The pin is low while an unmasked cause is set.",
        },
        EnumValue {
            name: "ACTIVE_HIGH",
            value: 1,
            description: "The pin is high while an unmasked cause is set.",
        },
    ];
    let mut info_axes = field("AXES", 0, 5, ReadOnly, "Number of axes.");
    info_axes.reset = axes;
    Block {
        name: "SAFETY",
        description: "E-stop, watchdog, drive enables and the interrupt line (docs/safety_io.md)",
        base: 0,
        address_bits: 7,
        registers: vec![
            reg("INFO", 0, ReadOnly, "Build parameters of the block.", "", vec![info_axes]),
            reg(
                "STATUS",
                1,
                ReadOnly,
                "Live state of the e-stop, the watchdog and the IRQ line.",
                "",
                vec![
                    with_reset(field("ESTOP_INPUT", 0, 1, ReadOnly, "The e-stop input, synchronised: 1 = it asks for a stop (low, or open)."), 1),
                    with_reset(field("ESTOP", 1, 1, ReadOnly, "The e-stop latch: every axis halted, every ENABLE output low. Set at reset."), 1),
                    field("BITTEN", 2, 1, ReadOnly, "Sticky: the watchdog has bitten (every axis halted, every ENABLE output low)."),
                    field("ARMED", 3, 1, ReadOnly, "The watchdog is counting."),
                    field("IRQ", 4, 1, ReadOnly, "An unmasked cause is set (the IRQ pin follows one clock later)."),
                ],
            ),
            reg(
                "CLEAR",
                2,
                WriteOnly,
                "Release the latches.",
                "ESTOP clears the e-stop latch only while STATUS.ESTOP_INPUT is 0; in the clock the input asks for a stop the latch stays set. BITTEN clears the bite flag unless the watchdog bites in the same clock.",
                vec![
                    field("ESTOP", 0, 1, WriteOnly, "Write 1 to clear the e-stop latch."),
                    field("BITTEN", 1, 1, WriteOnly, "Write 1 to clear the watchdog's bite flag."),
                ],
            ),
            reg(
                "ENABLE",
                3,
                ReadWrite,
                "Drive ENABLE output per axis.",
                "Cleared, and writes ignored, while ESTOP or BITTEN is set: after a stop the drives stay off until firmware enables them again.",
                axes_field(axes, ReadWrite, "One bit per axis; the pin is high while the bit is 1."),
            ),
            reg(
                "WDT_TIMEOUT",
                4,
                ReadWrite,
                "Watchdog timeout in clocks: the watchdog bites TIMEOUT + 1 clocks after the last arm or reload. 0 = off (the reset value).",
                "A write arms the watchdog (or disarms it, with 0) and loads WDT_COUNT with the value.",
                vec![field("VALUE", 0, 32, ReadWrite, "Clocks.")],
            ),
            reg(
                "WDT_RELOAD",
                5,
                WriteOnly,
                "Feed the watchdog.",
                "Writing KEY while ARMED loads WDT_COUNT from WDT_TIMEOUT; any other value, or a write while not armed, does nothing.",
                vec![field("KEY", 0, 32, WriteOnly, "The reload key.")],
            ),
            reg(
                "WDT_COUNT",
                6,
                ReadOnly,
                "Clocks left before the watchdog bites (it bites at the first edge where this is 0 and no reload is written).",
                "",
                vec![field("VALUE", 0, 32, ReadOnly, "Clocks.")],
            ),
            reg("IRQ_CTRL", 7, ReadWrite, "The IRQ pin.", "", vec![polarity]),
            reg(
                "CAUSE",
                8,
                WriteOneToClear,
                "Sticky interrupt causes of the whole card, set at the edge of their event.",
                "An event in the same clock as a write of 1 to its bit sets the bit.",
                system_causes(WriteOneToClear),
            ),
            reg("CAUSE_MASK", 9, ReadWrite, "Which CAUSE bits drive the IRQ pin.", "", system_causes(ReadWrite)),
            reg(
                "DONE_CAUSE",
                10,
                WriteOneToClear,
                "Sticky, per axis: the axis's move-done input rose.",
                "An event in the same clock as a write of 1 to its bit sets the bit.",
                axes_field(axes, WriteOneToClear, "One bit per axis."),
            ),
            reg("DONE_MASK", 11, ReadWrite, "Which DONE_CAUSE bits drive the IRQ pin.", "", axes_field(axes, ReadWrite, "One bit per axis.")),
            reg(
                "LOW_CAUSE",
                12,
                WriteOneToClear,
                "Sticky, per axis: the axis's FIFO-low input rose (time to refill).",
                "An event in the same clock as a write of 1 to its bit sets the bit.",
                axes_field(axes, WriteOneToClear, "One bit per axis."),
            ),
            reg("LOW_MASK", 13, ReadWrite, "Which LOW_CAUSE bits drive the IRQ pin.", "", axes_field(axes, ReadWrite, "One bit per axis.")),
        ]
        .into_iter()
        .chain(machine_registers(axes))
        .chain(gpio_registers())
        .chain([home_stop_register(axes)])
        .chain(soft_limit_registers(axes))
        .chain(counter_event_registers(axes))
        .collect(),
        arrays: vec![],
    }
}

/// Two per-axis fields: `low` at bit 0 and `high` at bit 16.
fn pair(
    axes: u32,
    access: Access,
    low: (&'static str, &'static str),
    high: (&'static str, &'static str),
) -> Vec<Field> {
    vec![
        field(low.0, 0, axes, access, low.1),
        field(high.0, 16, axes, access, high.1),
    ]
}

/// The machine inputs' registers (LIMIT_POS, LIMIT_NEG, HOME, ALARM per
/// axis): their control, filtered levels, causes and masks.
fn machine_registers(axes: u32) -> Vec<super::Register> {
    use Access::*;
    let ctrl = |name, offset, what: &'static str| {
        reg(
            name,
            offset,
            ReadWrite,
            what,
            "Both fields are 0 after reset: every input off and active high. The filters run whether an input is on or not, so its level is known before it is turned on.",
            pair(
                axes,
                ReadWrite,
                ("ENABLE", "Per axis: 1 = the input acts (sets its cause and, for limits and alarms, stops the axis)."),
                ("ACTIVE_LOW", "Per axis: 1 = the input is active while the pin is low (normally-closed switch to ground)."),
            ),
        )
    };
    let w1c_note =
        "An active input in the same clock as a write of 1 to its bit keeps the bit set.";
    vec![
        ctrl("LIMIT_POS_CTRL", 14, "The positive-direction limit inputs."),
        ctrl("LIMIT_NEG_CTRL", 15, "The negative-direction limit inputs."),
        ctrl("HOME_CTRL", 16, "The home switch inputs."),
        ctrl("ALARM_CTRL", 17, "The drive alarm inputs."),
        reg(
            "LIMIT_INPUTS",
            18,
            ReadOnly,
            "The limit inputs after synchroniser, filter and polarity: 1 = active (on or off).",
            "",
            pair(axes, ReadOnly, ("POS", "Per axis: LIMIT_POS active."), ("NEG", "Per axis: LIMIT_NEG active.")),
        ),
        reg(
            "HOME_ALARM_INPUTS",
            19,
            ReadOnly,
            "The home and alarm inputs after synchroniser, filter and polarity: 1 = active (on or off).",
            "",
            pair(axes, ReadOnly, ("HOME", "Per axis: HOME active."), ("ALARM", "Per axis: ALARM active.")),
        ),
        reg(
            "LIMIT_CAUSE",
            20,
            WriteOneToClear,
            "Sticky, per axis and direction: an enabled limit was active. While a bit is set the axis starts no step in that direction (it stops if it was heading that way); steps the other way stay allowed, so it can back off.",
            w1c_note,
            pair(axes, WriteOneToClear, ("POS", "Per axis: stopped at LIMIT_POS."), ("NEG", "Per axis: stopped at LIMIT_NEG.")),
        ),
        reg("LIMIT_MASK", 21, ReadWrite, "Which LIMIT_CAUSE bits drive the IRQ pin.", "", pair(axes, ReadWrite, ("POS", "Per axis."), ("NEG", "Per axis."))),
        reg(
            "HOME_ALARM_CAUSE",
            22,
            WriteOneToClear,
            "Sticky, per axis: HOME turned active (an edge), or an enabled ALARM was active (a level). While ALARM's bit is set the axis starts no step in either direction.",
            w1c_note,
            pair(axes, WriteOneToClear, ("HOME", "Per axis: the enabled HOME input turned active."), ("ALARM", "Per axis: stopped by the drive's alarm.")),
        ),
        reg("HOME_ALARM_MASK", 23, ReadWrite, "Which HOME_ALARM_CAUSE bits drive the IRQ pin.", "", pair(axes, ReadWrite, ("HOME", "Per axis."), ("ALARM", "Per axis."))),
    ]
}

/// Soft limits: the pulse bank compares each axis's POSITION with its
/// SOFT_MIN and SOFT_MAX; these registers turn the comparisons into causes
/// and stops as the limit inputs do.
fn soft_limit_registers(axes: u32) -> Vec<super::Register> {
    use Access::*;
    let halves = |access| {
        pair(
            axes,
            access,
            ("MAX", "Per axis: POSITION at or above PULSE.AX.SOFT_MAX."),
            ("MIN", "Per axis: POSITION at or below PULSE.AX.SOFT_MIN."),
        )
    };
    vec![
        reg(
            "SOFT_LIMIT_CTRL",
            32,
            ReadWrite,
            "Per axis and direction: 1 = the soft limit acts (sets its cause and stops the axis in that direction).",
            "0 after reset: no soft limit acts. Set PULSE.AX.SOFT_MIN and SOFT_MAX before turning one on.",
            halves(ReadWrite),
        ),
        reg(
            "SOFT_LIMIT_CAUSE",
            33,
            WriteOneToClear,
            "Sticky, per axis and direction: an enabled soft limit was reached. While MAX (MIN) is set the axis starts no step up (down) and stops if it heads that way; steps the other way stay allowed, so it can move back inside.",
            "A level, as LIMIT_CAUSE: a write of 1 clears the bit only once POSITION is back inside the limit.",
            halves(WriteOneToClear),
        ),
        reg("SOFT_LIMIT_MASK", 34, ReadWrite, "Which SOFT_LIMIT_CAUSE bits drive the IRQ pin.", "", halves(ReadWrite)),
    ]
}

/// The counter events: rises of each channel's STATUS.ERR and SEEN as
/// interrupt causes.
fn counter_event_registers(axes: u32) -> Vec<super::Register> {
    use Access::*;
    let halves = |access| {
        pair(
            axes,
            access,
            ("ERR", "Per counter channel: STATUS.ERR rose (an illegal quadrature transition, with CTRL.ERR_EN)."),
            ("INDEX", "Per counter channel: STATUS.SEEN rose (an index event)."),
        )
    };
    vec![
        reg(
            "COUNTER_CAUSE",
            35,
            WriteOneToClear,
            "Sticky, per counter channel: its STATUS.ERR or STATUS.SEEN rose (live, not through SNAPSHOT).",
            "An edge: a flag that stays set does not set its cause again; clear the channel's flag (CMD.CLEAR_STATUS) to see the next one. A rise in the same clock as a write of 1 keeps the bit set.",
            halves(WriteOneToClear),
        ),
        reg("COUNTER_MASK", 36, ReadWrite, "Which COUNTER_CAUSE bits drive the IRQ pin.", "", halves(ReadWrite)),
    ]
}

/// Stop on home: the register after the general-purpose I/O's.
fn home_stop_register(axes: u32) -> super::Register {
    reg(
        "HOME_STOP",
        31,
        Access::ReadWrite,
        "Per axis: 1 = while HOME_ALARM_CAUSE.HOME is set the axis starts no step in either direction (it stops on the home switch's edge, as at a limit); clear the cause to move on.",
        "0 after reset: HOME sets its cause and stops nothing.",
        axes_field(axes, Access::ReadWrite, "One bit per axis."),
    )
}

/// The general-purpose inputs' and outputs' registers.
fn gpio_registers() -> Vec<super::Register> {
    use Access::*;
    let ins = |access, what| vec![field("INPUTS", 0, GPIO_INPUTS, access, what)];
    let outs = |access, what| vec![field("OUTPUTS", 0, GPIO_OUTPUTS, access, what)];
    vec![
        reg(
            "GPI_LEVEL",
            24,
            ReadOnly,
            "The general-purpose inputs after synchroniser and filter (the machine inputs' filter time): 1 = the pin is high.",
            "",
            ins(ReadOnly, "Bit i = input i."),
        ),
        reg(
            "GPI_EDGE_CTRL",
            25,
            ReadWrite,
            "Which filtered edges of each input set GPI_CAUSE.",
            "Both fields are 0 after reset: no edge sets a cause.",
            vec![
                field("RISE", 0, GPIO_INPUTS, ReadWrite, "Bit i: a rise of input i sets its cause."),
                field("FALL", 16, GPIO_INPUTS, ReadWrite, "Bit i: a fall of input i sets its cause."),
            ],
        ),
        reg(
            "GPI_CAUSE",
            26,
            WriteOneToClear,
            "Sticky, per input: a selected edge of the filtered input.",
            "An edge in the same clock as a write of 1 to its bit sets the bit.",
            ins(WriteOneToClear, "Bit i = input i."),
        ),
        reg("GPI_MASK", 27, ReadWrite, "Which GPI_CAUSE bits drive the IRQ pin.", "", ins(ReadWrite, "Bit i = input i.")),
        reg(
            "GPO_VALUE",
            28,
            ReadWrite,
            "The general-purpose outputs' values: 1 = the pin high (push-pull) or released (open-drain).",
            "Loaded from GPO_SAFE, and writes ignored, while ESTOP or BITTEN is set: after a stop the outputs hold their safe state until firmware writes them again.",
            outs(ReadWrite, "Bit i = output i."),
        ),
        reg(
            "GPO_SAFE",
            29,
            ReadWrite,
            "Each output's safe state, taken by GPO_VALUE in the clock an e-stop or a watchdog bite halts the card (and from reset, which sets the e-stop latch).",
            "",
            outs(ReadWrite, "Bit i = output i's safe value."),
        ),
        reg(
            "GPO_OPEN_DRAIN",
            30,
            ReadWrite,
            "Per output: 1 = open-drain (drives low for 0, releases for 1; the board has the pull-up), 0 = push-pull (the reset value).",
            "",
            outs(ReadWrite, "Bit i = output i."),
        ),
    ]
}

// WDT_RELOAD's description names the key by field; the docs give its value.
const _: () = assert!(WATCHDOG_KEY != 0);
