//! A deterministic pin stimulus for the whole top (`motion_controller`),
//! implemented twice: in Rust ([`TopStimulus`], for the model and the
//! rust-hdl top) and as a Verilog testbench ([`verilog_testbench`], for
//! the generated Verilog in Icarus and Verilator, generating inside the
//! simulator for runs of 10^7 clocks). Both print checksums ([`Sums`]) of the
//! stimulus they applied and of every output pin, as
//! [`crate::checks::counter_bank::stimulus`] does for the counter bank, so a generator
//! mismatch shows as surely as a design mismatch.
//!
//! The stimulus, one draw of four xorshift32 words per clock:
//! * the STM32F4 FSMC at clock resolution (address phase 1–2 clocks, strobe
//!   6–7, a write's data late in the first strobe clock at random, one
//!   clock of hold, NE1# low across both halves of a 32-bit access):
//!   32-bit writes to every writable register (rates, timings, modes, RUN,
//!   segment staging and pushes, counter CTRL/CMD/PRESET/SNAPSHOT), 32-bit
//!   reads of every decoded register, lone 16-bit halves anywhere, RAM
//!   window reads and writes, other banks' cycles; idle gaps, some long
//!   enough for moves to run;
//! * the ISA bus at clock resolution (BALE 60 ns, command 6 clocks after
//!   BALE for 100–720 ns, 60 ns of address hold): all four registers,
//!   other cards' ports, DMA cycles (AEN high);
//! * every encoder a Gray phase that holds or steps (mostly forward), with
//!   an illegal jump every 8192 clocks and Z at phase 0;
//! * reset for the first clocks and again every 65536 clocks.

mod verilog;

pub use verilog::verilog_testbench;

use crate::checks::isa_bridge::TEST_BASE;
use motionhdl_model::machine_inputs::MachinePins;
use motionhdl_model::motion_controller::{TopInputs, TopOutputs};
use motionhdl_model::regmap::{self, Access};
use motionhdl_model::Config;

/// Clocks of reset at the start of every run.
pub const RESET_CLOCKS: u64 = 4;
/// Reset again for [`RESET_CLOCKS`] from this clock of every 65536.
pub const RERESET_AT: u64 = 32768;
/// The ISA base switches (the card answers on base*4..base*4+3).
pub const ISA_BASE: u8 = TEST_BASE;

/// Clocks between changes of the limit, home and alarm pins.
pub const MACHINE_EVERY: u64 = 1024;

/// Is clock `cycle` in reset?
pub fn reset_at(cycle: u64) -> bool {
    cycle < RESET_CLOCKS || (RERESET_AT..RERESET_AT + RESET_CLOCKS).contains(&(cycle % 65536))
}

// Bus states. Each lasts `count + 1` clocks; the clock on which `count` is
// 0 moves to the next state and shows its pins.
const IDLE: u8 = 0;
const ADDR: u8 = 1;
const STROBE: u8 = 2;
const HOLD: u8 = 3;
const BALE: u8 = 1;
const WAIT: u8 = 2;
const CMD: u8 = 3;
const ISA_HOLD: u8 = 4;

/// Data shaping per register (so rates pulse and timings stay short).
mod class {
    pub const RANDOM: u8 = 0;
    /// Signed, shifted right 1..=8: up to f/4 .. f/512.
    pub const RATE: u8 = 1;
    /// Two 16-bit halves of 0..=7 clocks.
    pub const TIMING: u8 = 2;
    /// 0..=7 (pulse CTRL).
    pub const SMALL: u8 = 3;
    /// 0..=255 (SEG_STEPS).
    pub const STEPS: u8 = 4;
    /// Signed, shifted right 20 (SEG_ACCEL, SEG_JERK).
    pub const ACCEL: u8 = 5;
    /// 0..=4095 (SOFT_MAX): a limit a few thousand steps up, so the
    /// random travel meets it now and then rather than at once.
    pub const NEAR: u8 = 6;
}

fn shape(c: u8, d: u32, shift: u32) -> u32 {
    match c {
        class::RATE => ((d as i32) >> shift) as u32,
        class::TIMING => (d & 7) | ((d >> 8) & 7) << 16,
        class::SMALL => d & 7,
        class::STEPS => d & 0xff,
        class::ACCEL => ((d as i32) >> 20) as u32,
        class::NEAR => d & 0xfff,
        _ => d,
    }
}

#[derive(Clone, Debug, Default)]
struct FsmcState {
    state: u8,
    count: u32,
    ours: bool,
    write: bool,
    two: bool,
    half: u16,
    a: u16,
    data: u32,
    late: bool,
    first: bool,
}

#[derive(Clone, Debug, Default)]
struct IsaState {
    state: u8,
    count: u32,
    port: u16,
    aen: bool,
    write: bool,
    data: u16,
    late: bool,
    first: bool,
}

/// The stimulus generator for the top of `config` (axes <= 16).
#[derive(Clone, Debug)]
pub struct TopStimulus {
    x: u32,
    cycle: u64,
    phase: Vec<u8>,
    /// Writable register words and their data class.
    writes: Vec<(u16, u8)>,
    /// Every decoded register word.
    reads: Vec<u16>,
    run_word: u16,
    axis_mask: u32,
    fsmc: FsmcState,
    isa: IsaState,
    pins: TopInputs,
}

impl TopStimulus {
    pub fn new(config: &Config, seed: u32) -> Self {
        let map = regmap::mcu_map(config);
        let mut writes = Vec::new();
        let mut reads = Vec::new();
        let mut run_word = 0;
        for b in &map.blocks {
            for (offset, r, _) in b.decoded() {
                let word = (b.base + offset) as u16;
                reads.push(word);
                if r.access == Access::ReadOnly {
                    continue;
                }
                if b.name == "PULSE" && r.name == "RUN" {
                    // RUN has its own, likelier op.
                    run_word = word;
                    continue;
                }
                let c = match (b.name, r.name) {
                    ("PULSE", "RATE" | "SEG_RATE") => class::RATE,
                    ("PULSE", "STEP_TIMING" | "DIR_TIMING") => class::TIMING,
                    ("PULSE", "CTRL") => class::SMALL,
                    ("PULSE", "SEG_STEPS") => class::STEPS,
                    ("PULSE", "SEG_ACCEL" | "SEG_JERK") => class::ACCEL,
                    ("PULSE", "SOFT_MAX") => class::NEAR,
                    // Timeouts of 0..=7 clocks one time in eight (the
                    // watchdog bites), else up to 2^19 (it rarely does);
                    // CLEAR's bits.
                    ("SAFETY", "WDT_TIMEOUT") => class::TIMING,
                    // Servo periods of 0..=255 clocks (shorter than a
                    // transfer too: overruns) and short DAC timings.
                    ("SERVO", "TICK_PERIOD") => class::STEPS,
                    ("SERVO", "TIMING") => class::SMALL,
                    ("SAFETY", "CLEAR") => class::SMALL,
                    // Inputs of axes 0..=2 on, active high: axis 3 never
                    // stops at a limit.
                    // Likewise the soft limits: MAX of axes 0..=2 only.
                    (
                        "SAFETY",
                        "LIMIT_POS_CTRL" | "LIMIT_NEG_CTRL" | "HOME_CTRL" | "ALARM_CTRL"
                        | "HOME_STOP" | "SOFT_LIMIT_CTRL",
                    ) => class::SMALL,
                    _ => class::RANDOM,
                };
                writes.push((word, c));
            }
        }
        assert!(run_word != 0, "PULSE.RUN");
        let axes = config.axes();
        assert!(axes <= 16);
        let mut pins = TopInputs::idle();
        pins.isa_base = ISA_BASE;
        Self {
            x: seed | 1,
            cycle: 0,
            phase: vec![0; axes as usize],
            writes,
            reads,
            run_word,
            axis_mask: (1 << axes) - 1,
            fsmc: FsmcState::default(),
            isa: IsaState::default(),
            pins,
        }
    }

    fn next(&mut self) -> u32 {
        crate::harness::xorshift32(&mut self.x)
    }

    /// The pins for the next clock.
    pub fn clock(&mut self) -> TopInputs {
        let r0 = self.next();
        let r1 = self.next();
        let r2 = self.next();
        let r3 = self.next();
        let p = &mut self.pins;
        p.reset = reset_at(self.cycle);

        // Encoders: a quarter of the clocks step, mostly forward.
        let moving = r0 >> 30 == 0;
        let jump = self.cycle % 8192 == 8191;
        let (mut a, mut b, mut z) = (0u16, 0u16, 0u16);
        for (i, ph) in self.phase.iter_mut().enumerate() {
            let m = (r0 >> ((2 * i as u32) % 28)) & 3;
            if jump {
                *ph = (*ph + 2) & 3;
            } else if moving && (m == 1 || m == 3) {
                *ph = (*ph + 1) & 3;
            } else if moving && m == 2 {
                *ph = (*ph + 3) & 3;
            }
            a |= u16::from(*ph == 1 || *ph == 2) << i;
            b |= u16::from(*ph == 2 || *ph == 3) << i;
            z |= u16::from(*ph == 0 && (r0 >> 29) & 1 == 1) << i;
        }
        p.enc_a = a;
        p.enc_b = b;
        p.enc_z = z;
        // Limit, home and alarm pins: random levels held MACHINE_EVERY
        // clocks, long enough to pass a short filter; limits active one
        // time in four, alarms one in sixteen, home one in two.
        if self.cycle.is_multiple_of(MACHINE_EVERY) {
            let mask = (1u32 << self.phase.len()) - 1;
            let sparse = r3 & r2;
            p.machine = MachinePins {
                limit_pos: sparse & mask,
                limit_neg: sparse >> 16 & mask,
                home: (r3 ^ r2) & mask,
                alarm: (sparse & sparse >> 4) >> 8 & mask,
                gpi: (r2 ^ r3 >> 7) & 0xffff,
            };
        }

        self.fsmc_clock(r1, r3);
        self.isa_clock(r2, r3);
        self.cycle += 1;
        self.pins
    }

    fn fsmc_clock(&mut self, r: u32, d: u32) {
        let f = &mut self.fsmc;
        let end_half = |f: &mut FsmcState| {
            if f.two && f.half == 0 {
                f.half = 1;
                f.state = ADDR;
                f.count = (r >> 28) & 1;
            } else {
                f.state = IDLE;
                f.count = if (r >> 24) & 31 == 0 {
                    64 + ((r >> 8) & 1023)
                } else {
                    (r >> 16) & 15
                };
            }
        };
        if f.count > 0 {
            f.count -= 1;
        } else {
            match f.state {
                IDLE => {
                    let kind = r & 15;
                    let idx = (r >> 8) & 0xfff;
                    let shift = 1 + ((r >> 20) & 7);
                    f.ours = true;
                    f.half = 0;
                    f.two = false;
                    f.write = false;
                    f.data = d;
                    match kind {
                        0..=4 => {
                            let (w, c) = self.writes[(idx % self.writes.len() as u32) as usize];
                            f.a = w * 2;
                            f.two = true;
                            f.write = true;
                            f.data = shape(c, d, shift);
                        }
                        5 => {
                            f.a = self.run_word * 2;
                            f.two = true;
                            f.write = true;
                            f.data = (d | d >> 8) & self.axis_mask;
                        }
                        6..=9 => {
                            f.a = self.reads[(idx % self.reads.len() as u32) as usize] * 2;
                            f.two = true;
                        }
                        10 => f.a = (idx & 0x7ff) as u16,
                        11 => {
                            f.a = (idx & 0x7ff) as u16;
                            f.write = true;
                        }
                        12 | 13 => {
                            f.a = 0x800 | (idx & 0x3ff) as u16;
                            f.write = true;
                        }
                        14 => f.a = 0x800 | (idx & 0x3ff) as u16,
                        _ => {
                            // Another bank: the strobes move, NE1# stays high.
                            f.ours = false;
                            f.write = (r >> 4) & 1 == 1;
                            f.a = idx as u16;
                        }
                    }
                    f.state = ADDR;
                    f.count = (r >> 28) & 1;
                }
                ADDR => {
                    f.state = STROBE;
                    f.count = 5 + ((r >> 29) & 1);
                    f.late = (r >> 30) & 1 == 1;
                    f.first = true;
                }
                STROBE if f.write => {
                    f.state = HOLD;
                    f.count = 0;
                }
                _ => end_half(f),
            }
        }
        let hd = if f.half == 1 { f.data >> 16 } else { f.data } as u16;
        let p = &mut self.pins;
        p.fsmc_ne_n = !(f.ours && f.state != IDLE);
        p.fsmc_noe_n = f.state != STROBE || f.write;
        p.fsmc_nwe_n = !(f.state == STROBE && f.write);
        p.fsmc_a = (f.a + f.half) & 0xfff;
        p.fsmc_d_in = match f.state {
            ADDR if f.write => !hd,
            STROBE if f.write && f.first && f.late => !hd,
            STROBE | HOLD if f.write => hd,
            _ => 0xffff,
        };
        if f.state == STROBE {
            f.first = false;
        }
    }

    fn isa_clock(&mut self, r: u32, d: u32) {
        let s = &mut self.isa;
        if s.count > 0 {
            s.count -= 1;
        } else {
            match s.state {
                IDLE => {
                    let kind = r & 15;
                    let reg = ((r >> 4) & 3) as u16;
                    s.write = (r >> 6) & 1 == 1;
                    s.aen = kind == 0;
                    let base = if kind == 1 || kind == 2 {
                        ISA_BASE ^ (1 + ((r >> 8) & 0x7f)) as u8
                    } else {
                        ISA_BASE
                    };
                    s.port = (u16::from(base) << 2) | reg;
                    s.data = (d >> 16) as u16;
                    s.state = BALE;
                    s.count = 2;
                }
                BALE => {
                    s.state = WAIT;
                    s.count = 2;
                }
                WAIT => {
                    s.state = CMD;
                    s.count = 4 + ((r >> 10) & 31);
                    s.late = (r >> 15) & 1 == 1;
                    s.first = true;
                }
                CMD => {
                    s.state = ISA_HOLD;
                    s.count = 2;
                }
                _ => {
                    s.state = IDLE;
                    s.count = if (r >> 20) & 15 == 0 {
                        50 + ((r >> 8) & 255)
                    } else {
                        (r >> 16) & 7
                    };
                }
            }
        }
        let p = &mut self.pins;
        p.isa_bale = s.state == BALE;
        p.isa_sa = s.port & 0x3ff;
        p.isa_aen = s.state != IDLE && s.aen;
        p.isa_ior_n = s.state != CMD || s.write;
        p.isa_iow_n = !(s.state == CMD && s.write);
        p.isa_sd_in = match s.state {
            CMD if s.write && s.first && s.late => 0xffff,
            CMD | ISA_HOLD if s.write => s.data,
            _ => 0xffff,
        };
        if s.state == CMD {
            s.first = false;
        }
    }
}

fn mix(sum: u32, v: u32) -> u32 {
    sum.wrapping_mul(31).wrapping_add(v)
}

/// Running checksums of the input pins applied and the output pins seen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sums {
    pub stimulus: u32,
    pub outputs: u32,
}

impl Sums {
    /// One clock: its input pins and the output pins before its edge.
    pub fn add(&mut self, p: &TopInputs, o: &TopOutputs) {
        let b = u32::from;
        for v in [
            b(p.fsmc_ne_n)
                | b(p.fsmc_noe_n) << 1
                | b(p.fsmc_nwe_n) << 2
                | b(p.reset) << 3
                | u32::from(p.fsmc_a) << 4
                | u32::from(p.fsmc_d_in) << 16,
            u32::from(p.isa_sa)
                | b(p.isa_ior_n) << 10
                | b(p.isa_iow_n) << 11
                | b(p.isa_aen) << 12
                | b(p.isa_bale) << 13
                | u32::from(p.isa_sd_in) << 16,
            u32::from(p.enc_a) | u32::from(p.enc_b) << 16,
            u32::from(p.enc_z),
            p.machine.limit_pos | p.machine.limit_neg << 16,
            p.machine.home | p.machine.alarm << 16,
            p.machine.gpi,
        ] {
            self.stimulus = mix(self.stimulus, v);
        }
        for v in [
            u32::from(o.fsmc_d_out)
                | b(o.fsmc_d_oe) << 16
                | b(o.isa_sd_oe) << 17
                | b(o.isa_iocs16_n) << 18
                | b(o.isa_irq) << 19,
            u32::from(o.isa_sd_out),
            u32::from(o.pulse_f1) | u32::from(o.pulse_f2) << 16,
            u32::from(o.drive_enable) | b(o.irq) << 16,
            u32::from(o.gpo_out) | u32::from(o.gpo_oe) << 16,
        ] {
            self.outputs = mix(self.outputs, v);
        }
    }
}
