//! The ISA bridge checks' stimulus: the exhaustive case set, block
//! transfers and random traffic, as bus-functional-model ops.

use crate::bfm::isa::{Op, CLOCK_PS, COMMAND_NS, HALF_NS, STANDARD_COMMAND_NS};
use crate::harness::Rng;
use motionhdl_model::isa_bridge::{self as m, mailbox, reg, status};
use motionhdl_model::regmap::ISA_RAM_WORDS;

/// The base used by the checks: ports 0x300..=0x303, the classic
/// prototype-card range.
pub const TEST_BASE: u8 = 0xc0;

pub(super) fn port_of(reg: u16) -> u16 {
    m::port(TEST_BASE, reg)
}

/// A port on another card: SA9..SA2 differ from the base.
pub(super) fn other_port(reg: u16) -> u16 {
    m::port(TEST_BASE ^ 0x5a, reg)
}

pub fn standard_write(reg: u16, data: u16) -> Op {
    Op::IoWrite {
        port: port_of(reg),
        aen: false,
        data,
        command_ns: STANDARD_COMMAND_NS,
    }
}

pub fn standard_read(reg: u16) -> Op {
    Op::IoRead {
        port: port_of(reg),
        aen: false,
        command_ns: STANDARD_COMMAND_NS,
    }
}

/// Phases of the bus against the FPGA clock: every whole nanosecond of the
/// 20 ns period, half a nanosecond off the edges (events are whole ns, so
/// these are all the distinct sampling patterns).
pub fn phases() -> impl Iterator<Item = u64> {
    (0..CLOCK_PS / 1000).map(|ns| ns * 1000 + 500)
}

/// Number of cases of [`exhaustive_ops`]:
/// register × read/write × AEN × match × phase × command length × AUTO_INC.
pub const EXHAUSTIVE_CASES: u64 = 4 * 2 * 2 * 2 * 20 * COMMAND_NS.len() as u64 * 2;

/// Every register × read/write × AEN × address match × strobe phase ×
/// command length × AUTO_INC, each case set up from reset, then observed by
/// reading STATUS and DATA from the PC and three words from the DSP.
pub fn exhaustive_ops() -> (Vec<Op>, u64) {
    let mut ops = Vec::new();
    let mut cases = 0;
    for phase in phases() {
        for &command_ns in &COMMAND_NS {
            for reg in 0..4u16 {
                for write in [false, true] {
                    for aen in [false, true] {
                        for matched in [false, true] {
                            for auto_inc in [false, true] {
                                let port = if matched {
                                    port_of(reg)
                                } else {
                                    other_port(reg)
                                };
                                let start = 5 | if auto_inc { status::AUTO_INC } else { 0 };
                                ops.extend([
                                    Op::Reset,
                                    Op::DspWrite {
                                        addr: 0,
                                        data: 0x9abc,
                                    },
                                    Op::DspWrite {
                                        addr: 5,
                                        data: 0x1234,
                                    },
                                    Op::DspWrite {
                                        addr: 6,
                                        data: 0x5678,
                                    },
                                    Op::Align { offset_ps: phase },
                                    standard_write(reg::STATUS, start),
                                    Op::Align { offset_ps: phase },
                                    if write {
                                        Op::IoWrite {
                                            port,
                                            aen,
                                            data: 0xc3a5,
                                            command_ns,
                                        }
                                    } else {
                                        Op::IoRead {
                                            port,
                                            aen,
                                            command_ns,
                                        }
                                    },
                                    Op::Align { offset_ps: phase },
                                    standard_read(reg::STATUS),
                                    Op::Align { offset_ps: phase },
                                    standard_read(reg::DATA),
                                    Op::DspRead { addr: 0 },
                                    Op::DspRead { addr: 5 },
                                    Op::DspRead { addr: 6 },
                                ]);
                                cases += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    (ops, cases)
}

/// A whole 2 KB block from the PC, read back by the PC and by the DSP;
/// then a block from the DSP read by the PC. `auto_inc` false is the seed's
/// way (DATA then ADDR_INC for every word), true the one-access-per-word
/// extension. `pattern` makes every run's data distinct.
pub fn block_transfer_ops(auto_inc: bool, pattern: u16) -> Vec<Op> {
    let word = |i: u16| i.wrapping_mul(0x9e37) ^ pattern;
    let mut ops = vec![Op::Reset];
    let start = |ops: &mut Vec<Op>| {
        ops.push(standard_write(reg::ADDR_CLEAR, 0));
        if auto_inc {
            ops.push(standard_write(reg::STATUS, status::AUTO_INC));
        }
    };
    start(&mut ops);
    for i in 0..ISA_RAM_WORDS as u16 {
        ops.push(standard_write(reg::DATA, word(i)));
        if !auto_inc {
            ops.push(standard_write(reg::ADDR_INC, 0));
        }
    }
    ops.push(standard_read(reg::STATUS));
    start(&mut ops);
    for _ in 0..ISA_RAM_WORDS {
        ops.push(standard_read(reg::DATA));
        if !auto_inc {
            ops.push(standard_read(reg::ADDR_INC));
        }
    }
    for addr in 0..ISA_RAM_WORDS as u16 {
        ops.push(Op::DspRead { addr });
    }
    // The other way: the DSP fills the RAM, the PC reads it.
    for addr in 0..ISA_RAM_WORDS as u16 {
        ops.push(Op::DspWrite {
            addr,
            data: !word(addr),
        });
    }
    start(&mut ops);
    for _ in 0..ISA_RAM_WORDS {
        ops.push(standard_read(reg::DATA));
        if !auto_inc {
            ops.push(standard_write(reg::ADDR_INC, 0));
        }
    }
    ops.push(standard_read(reg::STATUS));
    ops
}

/// Random bus traffic: I/O reads and writes of every register with random
/// data, command lengths (110..=600 ns) and phases; cycles to other cards'
/// ports and DMA cycles (AEN high) to this card's ports, which must change
/// nothing; DSP reads and writes between bus cycles (a DSP write lands
/// three clocks clear of any PC write, so the order is the op order).
pub fn random_ops(seed: u64, n: usize) -> Vec<Op> {
    let mut rng = Rng::new(seed);
    let mut ops = vec![Op::Reset];
    for _ in 0..n {
        let offset_ps = rng.below(20) * 1000 + HALF_NS;
        match rng.below(10) {
            0..=6 => {
                let reg = rng.below(4) as u16;
                let (port, aen) = match rng.below(10) {
                    0 => (other_port(reg), false),
                    1 => (port_of(reg), true),
                    _ => (port_of(reg), false),
                };
                let command_ns = 110 + rng.below(491);
                // STATUS writes mostly turn AUTO_INC on, so runs move.
                let data = rng.next_u64() as u16;
                ops.push(Op::Align { offset_ps });
                ops.push(if rng.below(2) == 0 {
                    Op::IoRead {
                        port,
                        aen,
                        command_ns,
                    }
                } else {
                    Op::IoWrite {
                        port,
                        aen,
                        data,
                        command_ns,
                    }
                });
            }
            7 => {
                ops.push(Op::Align { offset_ps });
                ops.push(Op::Align { offset_ps });
                // Half of them to the mailbox words, to ring both bells.
                let addr = match rng.below(4) {
                    0 => mailbox::TO_PC,
                    1 => mailbox::TO_DSP,
                    _ => rng.below(u64::from(ISA_RAM_WORDS)) as u16,
                };
                ops.push(Op::DspWrite {
                    addr,
                    data: rng.next_u64() as u16,
                });
            }
            8 => ops.push(Op::DspRead {
                addr: rng.below(u64::from(ISA_RAM_WORDS)) as u16,
            }),
            _ => {
                // Concentrate on a few words so reads meet earlier writes:
                // the two mailbox words at the top, and 0 and 1 after the
                // wrap; the IRQ enabled half the time.
                let word = (rng.below(4) as u16).wrapping_sub(2) & status::ADDR_MASK;
                let irq_en = if rng.below(2) == 0 { status::IRQ_EN } else { 0 };
                ops.push(Op::Align { offset_ps });
                ops.push(standard_write(
                    reg::STATUS,
                    word | irq_en | status::AUTO_INC,
                ));
            }
        }
    }
    ops.push(Op::Align { offset_ps: HALF_NS });
    ops.push(standard_read(reg::STATUS));
    ops
}

/// Seed and length of the long random run that goes through every simulator.
pub const LONG_RANDOM: (u64, usize) = (0x15a_b1d6e, 3000);
