//! The SERVO block: the DAC7744-style DAC output and the servo tick
//! (docs/servo_dac.md).

use super::{field, reg, with_reset, Access, Block, RegisterArray};
use crate::servo_dac::{
    clocks_for_ns, AD5686R_PREFIX, CS_LOW_NS, DAC_CHANNELS, LDAC_LOW_NS, SAFE_CODE, SCLK_HALF_NS,
    SYNC_HIGH_NS,
};

/// The servo DAC block for a clock of `clock_hz`: TIMING's and SERIAL's
/// reset values are the data sheets' minimum times in clocks.
pub fn servo_dac(clock_hz: u64) -> Block {
    use Access::*;
    let clocks = |ns: u64| clocks_for_ns(ns, clock_hz).clamp(1, 256) - 1;
    let events = |access: Access| {
        vec![
            field("TICK", 0, 1, access, "A servo tick: the counters' snapshot was taken and a transfer of the staged codes started."),
            field("OVERRUN", 1, 1, access, "A transfer was asked for while one ran: it waits (one deep) and its LOADDACS comes late."),
        ]
    };
    Block {
        name: "SERVO",
        description: "DAC output (DAC7744-style parallel interface) and the servo tick (docs/servo_dac.md)",
        base: 0,
        address_bits: 4,
        registers: vec![
            reg("INFO", 0, ReadOnly, "Build parameters of the block.", "", vec![with_reset(
                field("CHANNELS", 0, 4, ReadOnly, "DAC channels."),
                DAC_CHANNELS,
            )]),
            reg(
                "STATUS",
                1,
                ReadOnly,
                "Live state of the DAC interface.",
                "",
                vec![
                    field("BUSY", 0, 1, ReadOnly, "A transfer runs: the four writes and the LOADDACS pulse."),
                    field("PENDING", 1, 1, ReadOnly, "A transfer waits for the running one to end."),
                    field("SAFE", 2, 1, ReadOnly, "The safe input (e-stop, watchdog bite) is high: every transfer sends SAFE_CODE."),
                ],
            ),
            reg(
                "EVENTS",
                2,
                WriteOneToClear,
                "Sticky events, set at the edge of their event.",
                "An event in the same clock as a write of 1 to its bit sets the bit.",
                events(WriteOneToClear),
            ),
            reg(
                "TICK_PERIOD",
                3,
                ReadWrite,
                "Servo period in clocks: a tick every VALUE clocks. 0 = no tick (the reset value).",
                "A write restarts the period: the first tick is the clock VALUE clocks after the write's edge.",
                vec![field("VALUE", 0, 32, ReadWrite, "Clocks.")],
            ),
            reg(
                "UPDATE",
                4,
                WriteOnly,
                "Start a transfer of the staged codes now, as a tick would (without the snapshot).",
                "Any value.",
                vec![field("GO", 0, 1, WriteOnly, "Any value starts a transfer.")],
            ),
            reg(
                "TIMING",
                5,
                ReadWrite,
                "DAC interface timing in clocks.",
                "Takes effect from the next transfer.",
                vec![
                    with_reset(
                        field("CS_LOW", 0, 8, ReadWrite, "CS is low CS_LOW + 1 clocks per write (t_WCS)."),
                        clocks(CS_LOW_NS),
                    ),
                    with_reset(
                        field("LDAC_LOW", 8, 8, ReadWrite, "LOADDACS is low LDAC_LOW + 1 clocks (t_LWD)."),
                        clocks(LDAC_LOW_NS),
                    ),
                ],
            ),
            reg(
                "SERIAL",
                6,
                ReadWrite,
                "Which DAC interface the transfers drive, and the serial one's timing in clocks.",
                "Takes effect from the next transfer.",
                vec![
                    field("MODE", 0, 1, ReadWrite, "0: the DAC7744-style parallel pins (reset); 1: SPI frames on SCLK, SDIN, SYNC (CS stays high)."),
                    with_reset(
                        field("SCLK_HALF", 8, 8, ReadWrite, "SCLK is high SCLK_HALF + 1 clocks and low SCLK_HALF + 1 clocks per bit (t2, t3)."),
                        clocks(SCLK_HALF_NS),
                    ),
                    with_reset(
                        field("SYNC_HIGH", 16, 8, ReadWrite, "SYNC is high SYNC_HIGH + 1 clocks before each frame and before LDAC falls (t8)."),
                        clocks(SYNC_HIGH_NS),
                    ),
                ],
            ),
            reg(
                "PREFIX",
                7,
                ReadWrite,
                "The top 8 bits of each channel's 24-bit SPI frame: the DAC's command and channel address.",
                "Reset: the AD5686R's write-input-register command to DAC A..D; a transfer uses the values at its start.",
                (0..DAC_CHANNELS)
                    .map(|c| {
                        let name = ["CH0", "CH1", "CH2", "CH3"][c as usize];
                        with_reset(
                            field(name, 8 * c, 8, ReadWrite, "Frame bits 23:16 of the channel."),
                            AD5686R_PREFIX[c as usize],
                        )
                    })
                    .collect(),
            ),
        ],
        arrays: vec![RegisterArray {
            name: "CH",
            count: DAC_CHANNELS,
            offset: 8,
            stride: 2,
            registers: vec![
                reg(
                    "CODE",
                    0,
                    ReadWrite,
                    "The staged code of the channel, sent at the next transfer.",
                    "Straight binary: 0x0000 = -10 V, 0x8000 = 0 V, 0xFFFF = +10 V - 1 LSB.",
                    vec![with_reset(field("VALUE", 0, 16, ReadWrite, "DAC code."), SAFE_CODE)],
                ),
                reg(
                    "OUTPUT",
                    1,
                    ReadOnly,
                    "The code the DAC outputs: the one the last LOADDACS rise latched.",
                    "",
                    vec![with_reset(field("VALUE", 0, 16, ReadOnly, "DAC code."), SAFE_CODE)],
                ),
            ],
        }],
    }
}
