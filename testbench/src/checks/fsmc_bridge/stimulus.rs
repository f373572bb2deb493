//! The FSMC bridge checks' stimulus: the phase sweep and random traffic,
//! as bus-functional-model ops.

use super::LIVE_WORDS;
use crate::bfm::fsmc::{Op, PHASES};
use crate::harness::Rng;

/// Cases of [`phase_sweep_ops`] per phase.
pub const SWEEP_CASES_PER_PHASE: u64 = 12;
/// Cases of the phase sweep: [`PHASES`] × [`SWEEP_CASES_PER_PHASE`].
pub const SWEEP_CASES: u64 = PHASES as u64 * SWEEP_CASES_PER_PHASE;

/// Register and RAM addresses the sweep uses.
pub(super) const W_A: u16 = 0x0a5;
const W_B: u16 = 0x15a;
const W_C: u16 = 0x2c3;
const LIVE: u16 = 0x3f7;
const RAM: u16 = 0x800;

pub(super) fn reg_a(word: u16) -> u16 {
    word << 1
}

/// Every case at every one of the 84 phases of the HCLK grid against the
/// FPGA clock, each case aligned to the phase and its transactions back to
/// back (NE1# high for 1 + BUSTURN HCLKs between them). Returns the ops and
/// the number of cases.
pub fn phase_sweep_ops() -> (Vec<Op>, u64) {
    let mut ops = vec![Op::Reset];
    let mut cases = 0;
    for phase in 0..PHASES as u16 {
        let p = u32::from(phase);
        let d = |k: u32| 0x1000_0001u32.wrapping_mul(p * 16 + k + 1) ^ 0xa5c3_3c5a;
        let case: [Vec<Op>; SWEEP_CASES_PER_PHASE as usize] = [
            // 32-bit register write then read back.
            vec![
                Op::Write32 {
                    a: reg_a(W_A),
                    data: d(0),
                },
                Op::Read32 { a: reg_a(W_A) },
            ],
            // A live register read as 32 bits: one sample.
            vec![Op::Read32 { a: reg_a(LIVE) }],
            // The halves as separate transactions: the hold still serves.
            vec![
                Op::Read16 { a: reg_a(W_A) },
                Op::Read16 { a: reg_a(W_A) + 1 },
            ],
            // A lone high half reads afresh.
            vec![Op::Read16 { a: reg_a(W_B) + 1 }],
            // The halves of a write as separate transactions.
            vec![
                Op::Write16 {
                    a: reg_a(W_B),
                    data: d(1) as u16,
                },
                Op::Write16 {
                    a: reg_a(W_B) + 1,
                    data: (d(1) >> 16) as u16,
                },
                Op::Read32 { a: reg_a(W_B) },
            ],
            // RAM: 16-bit write and read.
            vec![
                Op::Write16 {
                    a: RAM | (phase * 7 % 1024),
                    data: d(2) as u16,
                },
                Op::Read16 {
                    a: RAM | (phase * 7 % 1024),
                },
            ],
            // RAM: 32-bit write, two words; read back as 32 and 16 bits.
            vec![
                Op::Write32 {
                    a: RAM | 0x200,
                    data: d(3),
                },
                Op::Read32 { a: RAM | 0x200 },
                Op::Read16 { a: RAM | 0x201 },
            ],
            // Another bank's cycles change nothing and are not answered.
            vec![
                Op::Other {
                    write: true,
                    a: reg_a(W_A) + 1,
                    data: 0x0bad,
                },
                Op::Other {
                    write: false,
                    a: reg_a(W_A),
                    data: 0,
                },
                Op::Read32 { a: reg_a(W_A) },
            ],
            // A lone high half of a live register.
            vec![Op::Read16 { a: reg_a(LIVE) + 1 }],
            // Write then read of another word straight after (no idle).
            vec![
                Op::Write32 {
                    a: reg_a(W_C),
                    data: !d(4),
                },
                Op::Read32 { a: reg_a(W_C) },
                Op::Read32 { a: reg_a(W_A) },
            ],
            // A low-half read of one word, then the high half of another:
            // the hold must not serve it.
            vec![
                Op::Read16 { a: reg_a(W_A) },
                Op::Read16 { a: reg_a(W_C) + 1 },
            ],
            // RAM then registers back to back, 16-bit reads of RAM words.
            vec![
                Op::Read16 { a: RAM | 0x200 },
                Op::Read32 { a: reg_a(W_B) },
                Op::Read16 {
                    a: RAM | (phase * 7 % 1024),
                },
            ],
        ];
        for c in case {
            ops.push(Op::Align { phase });
            ops.extend(c);
            cases += 1;
        }
    }
    (ops, cases)
}

/// Random traffic: 16- and 32-bit reads and writes of a few registers
/// (so reads meet earlier writes), live registers, RAM words, other banks'
/// cycles, random idle times and phases, an occasional reset.
pub fn random_ops(seed: u64, n: usize) -> Vec<Op> {
    let mut rng = Rng::new(seed);
    let mut ops = vec![Op::Reset];
    for _ in 0..n {
        let reg = |rng: &mut Rng| -> u16 {
            match rng.below(8) {
                0 => *LIVE_WORDS.start() + rng.below(16) as u16,
                1 => rng.below(1024) as u16,
                _ => rng.below(6) as u16 * 0x45,
            }
        };
        let ram = |rng: &mut Rng| -> u16 {
            RAM | if rng.below(2) == 0 {
                rng.below(8) as u16
            } else {
                rng.below(1024) as u16
            }
        };
        match rng.below(20) {
            0..=3 => ops.push(Op::Read32 {
                a: reg_a(reg(&mut rng)),
            }),
            4..=6 => ops.push(Op::Write32 {
                a: reg_a(reg(&mut rng)),
                data: rng.next_u64() as u32,
            }),
            7..=8 => ops.push(Op::Read16 {
                a: reg_a(reg(&mut rng)) | rng.below(2) as u16,
            }),
            9 => ops.push(Op::Write16 {
                a: reg_a(reg(&mut rng)) | rng.below(2) as u16,
                data: rng.next_u64() as u16,
            }),
            10..=11 => ops.push(Op::Read16 { a: ram(&mut rng) }),
            12..=13 => ops.push(Op::Write16 {
                a: ram(&mut rng),
                data: rng.next_u64() as u16,
            }),
            14 => {
                let a = ram(&mut rng) & !1;
                ops.push(if rng.below(2) == 0 {
                    Op::Read32 { a }
                } else {
                    Op::Write32 {
                        a,
                        data: rng.next_u64() as u32,
                    }
                });
            }
            15 => ops.push(Op::Other {
                write: rng.below(2) == 0,
                a: rng.below(4096) as u16,
                data: rng.next_u64() as u16,
            }),
            16 => ops.push(Op::Idle {
                hclk: rng.below(12) as u16,
            }),
            17..=18 => ops.push(Op::Align {
                phase: rng.below(u64::from(PHASES)) as u16,
            }),
            _ => {
                if rng.below(8) == 0 {
                    ops.push(Op::Reset);
                } else {
                    ops.push(Op::Read32 {
                        a: reg_a(rng.below(6) as u16 * 0x45),
                    });
                }
            }
        }
    }
    ops
}

/// Seed and length of the long random run that goes through every simulator.
pub const LONG_RANDOM: (u64, usize) = (0xf53c_b1d6, 1500);
