//! The whole top (`motion_controller`, RAM inside) against its model,
//! pin for pin, every clock; and a deterministic pin stimulus for it,
//! implemented twice: in Rust (for the model and the rust-hdl top) and as
//! a Verilog testbench (for the generated Verilog in Icarus and
//! Verilator). Both print checksums of the stimulus they applied and of
//! every output pin, as [`crate::counter_stimulus`] does for the counter
//! bank, so a generator mismatch shows as surely as a design mismatch.
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

use crate::bfm::fsmc::{timeline, Event, Op, CLOCK_TICKS, FIRST_EDGE_TICKS};
use crate::harness::{settle, CheckReport};
use crate::isa_bridge::TEST_BASE;
use crate::verilog_sim::{run_for_sums, Target};
use motionhdl_hdl::MotionController;
use motionhdl_model::fsmc_bridge::FsmcPins;
use motionhdl_model::motion_controller::{MotionControllerModel, TopInputs, TopOutputs};
use motionhdl_model::regmap::{self, Access};
use motionhdl_model::Config;
use rust_hdl::prelude::*;
use std::fmt::Write as _;

/// Clocks of reset at the start of every run.
pub const RESET_CLOCKS: u64 = 4;
/// Reset again for [`RESET_CLOCKS`] from this clock of every 65536.
pub const RERESET_AT: u64 = 32768;
/// The ISA base switches (the card answers on base*4..base*4+3).
pub const ISA_BASE: u8 = TEST_BASE;

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
    /// Signed, shifted right 20 (SEG_ACCEL).
    pub const ACCEL: u8 = 5;
}

fn shape(c: u8, d: u32, shift: u32) -> u32 {
    match c {
        class::RATE => ((d as i32) >> shift) as u32,
        class::TIMING => (d & 7) | ((d >> 8) & 7) << 16,
        class::SMALL => d & 7,
        class::STEPS => d & 0xff,
        class::ACCEL => ((d as i32) >> 20) as u32,
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
                    ("PULSE", "SEG_ACCEL") => class::ACCEL,
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
        ] {
            self.stimulus = mix(self.stimulus, v);
        }
        for v in [
            u32::from(o.fsmc_d_out)
                | b(o.fsmc_d_oe) << 16
                | b(o.isa_sd_oe) << 17
                | b(o.isa_iocs16_n) << 18,
            u32::from(o.isa_sd_out),
            u32::from(o.pulse_f1) | u32::from(o.pulse_f2) << 16,
        ] {
            self.outputs = mix(self.outputs, v);
        }
    }
}

/// The model's checksums after `cycles` clocks of stimulus from `seed`.
pub fn model_sums(config: &Config, seed: u32, cycles: u64) -> Sums {
    let mut s = TopStimulus::new(config, seed);
    let mut m = MotionControllerModel::new(config);
    let mut sums = Sums::default();
    for _ in 0..cycles {
        let p = s.clock();
        let o = m.step(&p);
        sums.add(&p, &o);
    }
    sums
}

/// Puts `p` on the rust-hdl top's input pins.
pub fn drive<const N: usize>(uut: &mut MotionController<N>, p: &TopInputs) {
    uut.reset.next = p.reset;
    uut.fsmc_ne_n.next = p.fsmc_ne_n;
    uut.fsmc_noe_n.next = p.fsmc_noe_n;
    uut.fsmc_nwe_n.next = p.fsmc_nwe_n;
    uut.fsmc_a.next = u64::from(p.fsmc_a & 0xfff).into();
    uut.fsmc_d_in.next = u64::from(p.fsmc_d_in).into();
    uut.isa_sa.next = u64::from(p.isa_sa & 0x3ff).into();
    uut.isa_sd_in.next = u64::from(p.isa_sd_in).into();
    uut.isa_ior_n.next = p.isa_ior_n;
    uut.isa_iow_n.next = p.isa_iow_n;
    uut.isa_aen.next = p.isa_aen;
    uut.isa_bale.next = p.isa_bale;
    uut.isa_base.next = u64::from(p.isa_base).into();
    uut.enc_a.next = u64::from(p.enc_a).into();
    uut.enc_b.next = u64::from(p.enc_b).into();
    uut.enc_z.next = u64::from(p.enc_z).into();
}

/// The rust-hdl top's output pins.
pub fn outputs<const N: usize>(uut: &MotionController<N>) -> TopOutputs {
    TopOutputs {
        fsmc_d_out: uut.fsmc_d_out.val().index() as u16,
        fsmc_d_oe: uut.fsmc_d_oe.val(),
        isa_sd_out: uut.isa_sd_out.val().index() as u16,
        isa_sd_oe: uut.isa_sd_oe.val(),
        isa_iocs16_n: uut.isa_iocs16_n.val(),
        pulse_f1: uut.pulse_f1.val().index() as u16,
        pulse_f2: uut.pulse_f2.val().index() as u16,
    }
}

/// One clock of the rust-hdl top: `p` on the pins, settle, the outputs
/// before the edge, then the rising and falling edges.
pub fn step_rust<const N: usize>(uut: &mut MotionController<N>, p: &TopInputs) -> TopOutputs {
    drive(uut, p);
    settle(uut);
    let o = outputs(uut);
    uut.clock.next = Clock::from(true);
    settle(uut);
    uut.clock.next = Clock::from(false);
    settle(uut);
    o
}

/// Per-clock FSMC pins and reset from the STM32F4 bus-functional model
/// (`fsmc_bridge::timeline`, documented timing): the pins as they are at
/// each rising edge.
pub fn bfm_clocks(ops: &[Op]) -> Vec<(FsmcPins, bool)> {
    let (events, end) = timeline(ops, &crate::bfm::fsmc::documented_timing());
    let mut out = Vec::new();
    let mut pins = FsmcPins::idle();
    let mut reset = false;
    let mut i = 0;
    let mut edge = FIRST_EDGE_TICKS;
    while edge <= end {
        while i < events.len() && events[i].0 < edge {
            if let Event::Pins(p, r) = events[i].1 {
                pins = p;
                reset = r;
            }
            i += 1;
        }
        out.push((pins, reset));
        edge += CLOCK_TICKS;
    }
    out
}

/// What one comparison run saw besides mismatches.
#[derive(Clone, Debug, Default)]
pub struct RunStats {
    /// Rising edges of F1 per axis (pulses came out).
    pub f1_edges: Vec<u64>,
    /// Clocks with FSMC D driven / ISA SD driven.
    pub fsmc_reads: u64,
    pub isa_reads: u64,
    /// Clocks in which some axis ran a segment (the model's move engines).
    pub move_clocks: u64,
}

/// Where a comparison's per-clock pins come from.
pub enum Pins<'a> {
    /// [`TopStimulus`] from this seed.
    Generated(u32),
    /// The FSMC pins from the bus-functional model (see [`bfm_clocks`]),
    /// the ISA pins and reset from [`TopStimulus`] (seed), and the encoder
    /// A/B inputs looped back from the pulse outputs F1/F2 of the clock
    /// before (Z from the generator).
    Bfm(&'a [(FsmcPins, bool)], u32),
}

/// The rust-hdl `MotionController<N>` and the model side by side for
/// `cycles` clocks: every output pin compared every clock (one case per
/// clock). `fault` may alter the model's outputs before the comparison
/// (to show that a wrong model is caught).
pub fn compare<const N: usize>(
    config: &Config,
    pins: Pins,
    cycles: u64,
    mut fault: impl FnMut(u64, &mut TopOutputs),
) -> (CheckReport, RunStats) {
    let what = match pins {
        Pins::Generated(seed) => format!("generated pin stimulus, seed {seed}"),
        Pins::Bfm(..) => "STM32F4 FSMC bus-functional model, ISA traffic, pulse loopback".into(),
    };
    let mut r = CheckReport::new(
        "motion_controller",
        &format!("every output pin every clock, {cycles} clocks, {what}: rust-hdl vs model"),
        cycles,
    );
    let mut stats = RunStats {
        f1_edges: vec![0; N],
        ..Default::default()
    };
    let (seed, bfm) = match pins {
        Pins::Generated(s) => (s, None),
        Pins::Bfm(v, s) => (s, Some(v)),
    };
    let mut stim = TopStimulus::new(config, seed);
    let mut model = MotionControllerModel::new(config);
    let mut uut = MotionController::<N>::new(config);
    uut.connect_all();
    let mut last = TopOutputs::default();
    for k in 0..cycles {
        let mut p = stim.clock();
        if let Some(v) = bfm {
            let (f, reset) = v
                .get(k as usize)
                .copied()
                .unwrap_or((FsmcPins::idle(), false));
            p.fsmc_ne_n = f.ne_n;
            p.fsmc_noe_n = f.noe_n;
            p.fsmc_nwe_n = f.nwe_n;
            p.fsmc_a = f.a;
            p.fsmc_d_in = f.d_in;
            p.reset = reset || k < RESET_CLOCKS;
            p.enc_a = last.pulse_f1;
            p.enc_b = last.pulse_f2;
        }
        let got = step_rust(&mut uut, &p);
        let mut want = model.step(&p);
        fault(k, &mut want);
        let bad: Vec<String> = got
            .pins()
            .iter()
            .zip(want.pins())
            .filter(|(g, w)| g.1 != w.1)
            .map(|(g, w)| format!("{} HDL {:#x} model {:#x}", g.0, g.1, w.1))
            .collect();
        r.case((!bad.is_empty()).then(|| format!("clock {k}: {}; inputs {p:?}", bad.join(", "))));
        if r.failures.len() >= 5 {
            break;
        }
        for (i, e) in stats.f1_edges.iter_mut().enumerate() {
            *e += u64::from(got.pulse_f1 >> i & 1 == 1 && last.pulse_f1 >> i & 1 == 0);
        }
        stats.fsmc_reads += u64::from(got.fsmc_d_oe);
        stats.isa_reads += u64::from(got.isa_sd_oe);
        stats.move_clocks += u64::from((0..N).any(|i| model.pulses().engine(i).active()));
        last = got;
    }
    (r, stats)
}

/// The Verilog testbench: the same generator driving `motion_controller`,
/// sampling the outputs at each rising edge (before it acts).
pub fn verilog_testbench(config: &Config, seed: u32, cycles: u64) -> String {
    let s = TopStimulus::new(config, seed);
    let n = config.axes();
    let top = n - 1;
    let mut writes = String::new();
    for (i, (w, c)) in s.writes.iter().enumerate() {
        let _ = writeln!(
            writes,
            "                {i}: begin write_word = 12'd{w}; write_class = 3'd{c}; end"
        );
    }
    let mut reads = String::new();
    for (i, w) in s.reads.iter().enumerate() {
        let _ = writeln!(reads, "                {i}: read_word = 12'd{w};");
    }
    format!(
        r#"`timescale 1ns / 1ps
`default_nettype none
module top_bench_tb;
    reg clock;
    reg reset;
    reg fsmc_ne_n, fsmc_noe_n, fsmc_nwe_n;
    reg [11:0] fsmc_a;
    reg [15:0] fsmc_d_in;
    wire [15:0] fsmc_d_out;
    wire fsmc_d_oe;
    reg [9:0] isa_sa;
    reg [15:0] isa_sd_in;
    reg isa_ior_n, isa_iow_n, isa_aen, isa_bale;
    wire [15:0] isa_sd_out;
    wire isa_sd_oe, isa_iocs16_n;
    reg [{top}:0] enc_a, enc_b, enc_z;
    wire [{top}:0] pulse_f1, pulse_f2;
    motion_controller dut (
        .clock(clock), .reset(reset),
        .fsmc_ne_n(fsmc_ne_n), .fsmc_noe_n(fsmc_noe_n), .fsmc_nwe_n(fsmc_nwe_n),
        .fsmc_a(fsmc_a), .fsmc_d_in(fsmc_d_in), .fsmc_d_out(fsmc_d_out), .fsmc_d_oe(fsmc_d_oe),
        .isa_sa(isa_sa), .isa_sd_in(isa_sd_in), .isa_sd_out(isa_sd_out), .isa_sd_oe(isa_sd_oe),
        .isa_ior_n(isa_ior_n), .isa_iow_n(isa_iow_n), .isa_aen(isa_aen), .isa_bale(isa_bale),
        .isa_base(8'd{base}), .isa_iocs16_n(isa_iocs16_n),
        .enc_a(enc_a), .enc_b(enc_b), .enc_z(enc_z),
        .pulse_f1(pulse_f1), .pulse_f2(pulse_f2)
    );
    reg [31:0] x, r0, r1, r2, r3, sum_stim, sum_out, idx, shift, m;
    reg [63:0] cycle;
    reg [1:0] phase [0:{top}];
    reg [15:0] a16, b16, z16, hd;
    reg moving, jump;
    integer i;
    // FSMC generator
    reg [1:0] f_state;
    reg [31:0] f_count, f_data;
    reg f_ours, f_write, f_two, f_late, f_first;
    reg [11:0] f_a;
    reg [11:0] f_half;
    // ISA generator
    reg [2:0] i_state;
    reg [31:0] i_count;
    reg [9:0] i_port;
    reg [7:0] i_base;
    reg i_aen, i_write, i_late, i_first;
    reg [15:0] i_data;
    reg [11:0] write_word, read_word;
    reg [2:0] write_class;

    function [31:0] xorshift(input [31:0] v);
        reg [31:0] y;
        begin
            y = v ^ (v << 13);
            y = y ^ (y >> 17);
            xorshift = y ^ (y << 5);
        end
    endfunction

    function [31:0] shape(input [2:0] c, input [31:0] d, input [31:0] sh);
        begin
            case (c)
                3'd{c_rate}: shape = $signed(d) >>> sh;
                3'd{c_timing}: shape = (d & 32'd7) | (((d >> 8) & 32'd7) << 16);
                3'd{c_small}: shape = d & 32'd7;
                3'd{c_steps}: shape = d & 32'd255;
                3'd{c_accel}: shape = $signed(d) >>> 20;
                default: shape = d;
            endcase
        end
    endfunction

    task lookup_write(input [31:0] k);
        begin
            write_word = 12'd0; write_class = 3'd0;
            case (k)
{writes}                default: ;
            endcase
        end
    endtask

    task lookup_read(input [31:0] k);
        begin
            read_word = 12'd0;
            case (k)
{reads}                default: ;
            endcase
        end
    endtask

    task fsmc_end_half;
        begin
            if (f_two && f_half == 12'd0) begin
                f_half = 12'd1; f_state = 2'd{addr}; f_count = (r1 >> 28) & 32'd1;
            end else begin
                f_state = 2'd{idle};
                if (((r1 >> 24) & 32'd31) == 32'd0) f_count = 32'd64 + ((r1 >> 8) & 32'd1023);
                else f_count = (r1 >> 16) & 32'd15;
            end
        end
    endtask

    task fsmc_clock;
        begin
            if (f_count != 32'd0) f_count = f_count - 32'd1;
            else case (f_state)
                2'd{idle}: begin
                    idx = (r1 >> 8) & 32'hfff;
                    shift = 32'd1 + ((r1 >> 20) & 32'd7);
                    f_ours = 1'b1; f_half = 12'd0; f_two = 1'b0; f_write = 1'b0; f_data = r3;
                    case (r1 & 32'd15)
                        32'd0, 32'd1, 32'd2, 32'd3, 32'd4: begin
                            lookup_write(idx % 32'd{n_writes});
                            f_a = write_word << 1; f_two = 1'b1; f_write = 1'b1;
                            f_data = shape(write_class, r3, shift);
                        end
                        32'd5: begin
                            f_a = 12'd{run_a}; f_two = 1'b1; f_write = 1'b1; f_data = (r3 | (r3 >> 8)) & 32'd{axis_mask};
                        end
                        32'd6, 32'd7, 32'd8, 32'd9: begin
                            lookup_read(idx % 32'd{n_reads});
                            f_a = read_word << 1; f_two = 1'b1;
                        end
                        32'd10: f_a = 12'(idx & 32'h7ff);
                        32'd11: begin f_a = 12'(idx & 32'h7ff); f_write = 1'b1; end
                        32'd12, 32'd13: begin f_a = 12'h800 | 12'(idx & 32'h3ff); f_write = 1'b1; end
                        32'd14: f_a = 12'h800 | 12'(idx & 32'h3ff);
                        default: begin f_ours = 1'b0; f_write = r1[4]; f_a = 12'(idx); end
                    endcase
                    f_state = 2'd{addr}; f_count = (r1 >> 28) & 32'd1;
                end
                2'd{addr}: begin
                    f_state = 2'd{strobe}; f_count = 32'd5 + ((r1 >> 29) & 32'd1);
                    f_late = r1[30]; f_first = 1'b1;
                end
                2'd{strobe}: begin
                    if (f_write) begin f_state = 2'd{hold}; f_count = 32'd0; end
                    else fsmc_end_half;
                end
                default: fsmc_end_half;
            endcase
            hd = f_half == 12'd1 ? f_data[31:16] : f_data[15:0];
            fsmc_ne_n = !(f_ours && f_state != 2'd{idle});
            fsmc_noe_n = !(f_state == 2'd{strobe} && !f_write);
            fsmc_nwe_n = !(f_state == 2'd{strobe} && f_write);
            fsmc_a = f_a + f_half;
            if (f_state == 2'd{addr} && f_write) fsmc_d_in = ~hd;
            else if (f_state == 2'd{strobe} && f_write && f_first && f_late) fsmc_d_in = ~hd;
            else if ((f_state == 2'd{strobe} || f_state == 2'd{hold}) && f_write) fsmc_d_in = hd;
            else fsmc_d_in = 16'hffff;
            if (f_state == 2'd{strobe}) f_first = 1'b0;
        end
    endtask

    task isa_clock;
        begin
            if (i_count != 32'd0) i_count = i_count - 32'd1;
            else case (i_state)
                3'd{idle}: begin
                    i_write = r2[6];
                    i_aen = (r2 & 32'd15) == 32'd0;
                    if ((r2 & 32'd15) == 32'd1 || (r2 & 32'd15) == 32'd2)
                        i_base = 8'd{base} ^ 8'(32'd1 + ((r2 >> 8) & 32'h7f));
                    else i_base = 8'd{base};
                    i_port = {{i_base, r2[5:4]}};
                    i_data = r3[31:16];
                    i_state = 3'd{bale}; i_count = 32'd2;
                end
                3'd{bale}: begin i_state = 3'd{wait_}; i_count = 32'd2; end
                3'd{wait_}: begin
                    i_state = 3'd{cmd}; i_count = 32'd4 + ((r2 >> 10) & 32'd31);
                    i_late = r2[15]; i_first = 1'b1;
                end
                3'd{cmd}: begin i_state = 3'd{isa_hold}; i_count = 32'd2; end
                default: begin
                    i_state = 3'd{idle};
                    if (((r2 >> 20) & 32'd15) == 32'd0) i_count = 32'd50 + ((r2 >> 8) & 32'd255);
                    else i_count = (r2 >> 16) & 32'd7;
                end
            endcase
            isa_bale = i_state == 3'd{bale};
            isa_sa = i_port;
            isa_aen = i_state != 3'd{idle} && i_aen;
            isa_ior_n = !(i_state == 3'd{cmd} && !i_write);
            isa_iow_n = !(i_state == 3'd{cmd} && i_write);
            if (i_state == 3'd{cmd} && i_write && i_first && i_late) isa_sd_in = 16'hffff;
            else if ((i_state == 3'd{cmd} || i_state == 3'd{isa_hold}) && i_write) isa_sd_in = i_data;
            else isa_sd_in = 16'hffff;
            if (i_state == 3'd{cmd}) i_first = 1'b0;
        end
    endtask

    // The next clock's pins, applied at the falling edge (and once at the
    // start for the first rising edge).
    task gen;
        begin
            x = xorshift(x); r0 = x;
            x = xorshift(x); r1 = x;
            x = xorshift(x); r2 = x;
            x = xorshift(x); r3 = x;
            reset = cycle < 64'd{reset_clocks} ||
                ((cycle % 64'd65536) >= 64'd{rereset} && (cycle % 64'd65536) < 64'd{rereset_end});
            moving = (r0 >> 30) == 32'd0;
            jump = (cycle % 64'd8192) == 64'd8191;
            a16 = 16'd0; b16 = 16'd0; z16 = 16'd0;
            for (i = 0; i < {n}; i = i + 1) begin
                m = (r0 >> ((2 * i) % 28)) & 32'd3;
                if (jump) phase[i] = phase[i] + 2'd2;
                else if (moving && (m == 32'd1 || m == 32'd3)) phase[i] = phase[i] + 2'd1;
                else if (moving && m == 32'd2) phase[i] = phase[i] + 2'd3;
                a16[i] = phase[i] == 2'd1 || phase[i] == 2'd2;
                b16[i] = phase[i] == 2'd2 || phase[i] == 2'd3;
                z16[i] = phase[i] == 2'd0 && r0[29];
            end
            enc_a = a16[{top}:0]; enc_b = b16[{top}:0]; enc_z = z16[{top}:0];
            fsmc_clock;
            isa_clock;
            sum_stim = sum_stim * 32'd31 + {{fsmc_d_in, fsmc_a, reset, fsmc_nwe_n, fsmc_noe_n, fsmc_ne_n}};
            sum_stim = sum_stim * 32'd31 + {{isa_sd_in, 2'd0, isa_bale, isa_aen, isa_iow_n, isa_ior_n, isa_sa}};
            sum_stim = sum_stim * 32'd31 + {{b16, a16}};
            sum_stim = sum_stim * 32'd31 + {{16'd0, z16}};
            cycle = cycle + 64'd1;
        end
    endtask

    always #5 clock = ~clock;
    initial begin
        clock = 1'b0;
        x = 32'd{seed};
        sum_stim = 32'd0;
        sum_out = 32'd0;
        cycle = 64'd0;
        for (i = 0; i < {n}; i = i + 1) phase[i] = 2'd0;
        f_state = 2'd{idle}; f_count = 32'd0; f_data = 32'd0; f_ours = 1'b0; f_write = 1'b0;
        f_two = 1'b0; f_late = 1'b0; f_first = 1'b0; f_a = 12'd0; f_half = 12'd0;
        i_state = 3'd{idle}; i_count = 32'd0; i_port = 10'd0; i_aen = 1'b0; i_write = 1'b0;
        i_late = 1'b0; i_first = 1'b0; i_data = 16'd0;
        gen;
    end
    // The outputs before the edge acts (the design's flops update after).
    always @(posedge clock) begin
        sum_out = sum_out * 32'd31 + {{13'd0, isa_iocs16_n, isa_sd_oe, fsmc_d_oe, fsmc_d_out}};
        sum_out = sum_out * 32'd31 + {{16'd0, isa_sd_out}};
        sum_out = sum_out * 32'd31 + {{16'(pulse_f2), 16'(pulse_f1)}};
    end
    // (Icarus starts the clock at X: X -> 0 at time 0 is no clock.)
    always @(negedge clock) if ($time != 0) begin
        if (cycle == 64'd{cycles}) begin
            $display("SUMS %0d %0d", sum_stim, sum_out);
            $finish;
        end else gen;
    end
endmodule
"#,
        base = ISA_BASE,
        seed = s.x,
        n = n,
        top = top,
        cycles = cycles,
        reset_clocks = RESET_CLOCKS,
        rereset = RERESET_AT,
        rereset_end = RERESET_AT + RESET_CLOCKS,
        n_writes = s.writes.len(),
        n_reads = s.reads.len(),
        run_a = s.run_word * 2,
        axis_mask = s.axis_mask,
        writes = writes,
        reads = reads,
        c_rate = class::RATE,
        c_timing = class::TIMING,
        c_small = class::SMALL,
        c_steps = class::STEPS,
        c_accel = class::ACCEL,
        idle = IDLE,
        addr = ADDR,
        strobe = STROBE,
        hold = HOLD,
        bale = BALE,
        wait_ = WAIT,
        cmd = CMD,
        isa_hold = ISA_HOLD,
    )
}

/// Runs `motion_controller.v` for `config` (the generated file, or its
/// post-synthesis netlist) under [`verilog_testbench`] in the target's
/// simulator: its checksums, and how long the simulation ran (compilation
/// and synthesis excluded).
pub fn verilog_sums_timed(
    target: impl Into<Target>,
    config: &Config,
    seed: u32,
    cycles: u64,
) -> Result<(Sums, std::time::Duration), String> {
    let target = target.into();
    target.available()?;
    let text = target.text(&motionhdl_hdl::catalog::motion_controller(config))?;
    let (v, elapsed) = run_for_sums(
        target.sim,
        &[
            ("tb.v", verilog_testbench(config, seed, cycles)),
            ("motion_controller.v", text),
        ],
        "top_bench_tb",
    )?;
    Ok((
        Sums {
            stimulus: v[0],
            outputs: v[1],
        },
        elapsed,
    ))
}
