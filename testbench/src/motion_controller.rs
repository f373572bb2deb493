//! The top level through the MCU's pins: every register of the map and the
//! shared RAM window read and written by the STM32F4 FSMC bus-functional
//! model (`fsmc_bridge`'s, with the documented timing), in rust-hdl and in
//! the generated `motion_controller.v`, against an oracle built from the
//! register-map table, the counter bank model and a RAM array.

use crate::bfm::fsmc::{
    self, documented_timing, timeline, Event, Observation, Op, CLOCK_TICKS, FIRST_EDGE_TICKS,
};
use crate::harness::{settle, CheckReport};
use crate::player::{PinStream, Rig};
use crate::verilog_sim::{Simulator, Source, Target};
use motionhdl_hdl::{catalog, MotionController, MotionControllerExternal};
use motionhdl_model::counter::{Bank, BusCycle, CounterParams};
use motionhdl_model::fsmc_bridge::FsmcPins;
use motionhdl_model::pulse_generator::PulseBank;
use motionhdl_model::regmap::{self, Access, BusMap, ERR_COUNT_BITS};
use motionhdl_model::{Config, IsaRam};
use rust_hdl::prelude::*;

/// Register word addresses the MCU bus decodes into (A[10:1]).
pub const REGISTER_WORDS: u32 = 1 << (regmap::MCU_HALFWORD_ADDRESS_BITS - 2);
/// Halfword address of the RAM window's word 0 (pin A11).
pub const RAM_HALFWORD: u16 = (regmap::MCU_RAM_BYTE_OFFSET / 2) as u16;
/// Clocks the oracle's counter bank runs after each write, so that the
/// write's consequences (an index event after a CTRL write, a two-edge
/// LOAD) have settled before anything reads them.
const SETTLE_CLOCKS: u32 = 40;

/// What the MCU must read, from the table and the models.
pub struct McuOracle {
    map: BusMap,
    bank: Bank,
    pulses: PulseBank,
    axes: usize,
    ram: Vec<u16>,
}

impl McuOracle {
    pub fn new(config: &Config) -> Self {
        let map = regmap::mcu_map(config);
        let bank = Bank::new(
            config.axes(),
            CounterParams::new(config.counter_width(), ERR_COUNT_BITS),
        );
        let words = map.memories.first().map_or(0, |m| m.words) as usize;
        Self {
            map,
            bank,
            pulses: PulseBank::new(config.axes(), config.counter_width()),
            axes: config.axes() as usize,
            ram: vec![0; words],
        }
    }

    pub fn map(&self) -> &BusMap {
        &self.map
    }

    /// One clock of the counter bank (bus `bus`) and the pulse bank (bus
    /// `pulse_bus`); the counter's SNAPSHOT also captures the pulses.
    fn clock_both(&mut self, reset: bool, bus: &BusCycle, pulse_bus: &BusCycle) {
        let pins = vec![(false, false, false); self.axes];
        let counter = self.map.block("COUNTER");
        let snapshot = bus.we && bus.addr == counter.register("SNAPSHOT").offset;
        self.bank.clock(&pins, reset, bus);
        self.pulses.clock(reset, pulse_bus, snapshot);
    }

    fn clock_bank(&mut self, reset: bool, bus: &BusCycle) {
        self.clock_both(reset, bus, &BusCycle::default());
    }

    /// The synchronous reset: registers to their reset values, RAM kept.
    pub fn reset(&mut self) {
        for _ in 0..5 {
            self.clock_bank(true, &BusCycle::default());
        }
        for _ in 0..SETTLE_CLOCKS {
            self.clock_bank(false, &BusCycle::default());
        }
    }

    /// The block decoding register word `word`, and the word's offset in it.
    pub fn decode(&self, word: u32) -> Option<(&'static str, u32)> {
        self.map
            .blocks
            .iter()
            .find(|b| word >> b.address_bits == b.base >> b.address_bits)
            .map(|b| (b.name, word - b.base))
    }

    /// Whether a write to `word` may change what any read returns.
    pub fn writable(&self, word: u32) -> bool {
        match self.decode(word) {
            Some((block @ ("COUNTER" | "PULSE"), offset)) => self
                .map
                .block(block)
                .decoded()
                .iter()
                .any(|(o, r, _)| *o == offset && r.access != Access::ReadOnly),
            _ => false,
        }
    }

    /// A 32-bit write to register word `word`.
    pub fn write32(&mut self, word: u32, data: u32) {
        let idle = BusCycle::default();
        match self.decode(word) {
            Some(("COUNTER", offset)) => {
                self.clock_both(false, &BusCycle::write(offset, data), &idle)
            }
            Some(("PULSE", offset)) => {
                self.clock_both(false, &idle, &BusCycle::write(offset, data))
            }
            _ => return,
        }
        for _ in 0..SETTLE_CLOCKS {
            self.clock_bank(false, &idle);
        }
    }

    /// A 32-bit read of register word `word`.
    pub fn read32(&self, word: u32) -> u32 {
        match self.decode(word) {
            Some(("ID", offset)) => self
                .map
                .block("ID")
                .registers
                .iter()
                .find(|r| r.offset == offset)
                .map_or(0, |r| r.reset),
            Some(("COUNTER", offset)) => self.bank.read_value(offset),
            Some(("PULSE", offset)) => self.pulses.read_value(offset),
            Some((other, _)) => panic!("oracle has no model of block {other}"),
            None => 0,
        }
    }

    pub fn ram_write(&mut self, word: usize, data: u16) {
        self.ram[word] = data;
    }

    pub fn ram_read(&self, word: usize) -> u16 {
        self.ram[word]
    }
}

/// The op list and, per read access (halfword), the value it must return.
pub struct Plan {
    pub ops: Vec<Op>,
    pub expected: Vec<u16>,
    /// Register words written that the map decodes to nothing writable.
    pub ignored_writes: u64,
}

/// A deterministic pattern with every bit exercised over the words.
fn pattern(word: u32, salt: u32) -> u32 {
    let x = word.wrapping_mul(0x9E37_79B9) ^ salt;
    x ^ (x >> 15) ^ (x << 7)
}

/// Every register word read after reset; a pattern written to every word
/// that decodes to nothing writable (reserved, ID, read-only) and every word
/// read again; PRESET, LOAD, CTRL and SNAPSHOT written for every channel,
/// every PULSE register but RUN for every axis (with 1..=5 segment pushes),
/// and every word read again; every RAM word written and read back, as 16-bit
/// and as 32-bit accesses.
pub fn plan(config: &Config) -> Plan {
    let mut o = McuOracle::new(config);
    let mut ops = vec![Op::Reset];
    let mut expected = Vec::new();
    o.reset();
    let read_all = |o: &McuOracle, ops: &mut Vec<Op>, expected: &mut Vec<u16>| {
        for w in 0..REGISTER_WORDS {
            ops.push(Op::Read32 { a: (w * 2) as u16 });
            let v = o.read32(w);
            expected.extend([v as u16, (v >> 16) as u16]);
        }
    };
    read_all(&o, &mut ops, &mut expected);
    let mut ignored_writes = 0;
    for w in 0..REGISTER_WORDS {
        if !o.writable(w) {
            let data = pattern(w, 0x5A5A_A5A5);
            ops.push(Op::Write32 {
                a: (w * 2) as u16,
                data,
            });
            o.write32(w, data);
            ignored_writes += 1;
        }
    }
    read_all(&o, &mut ops, &mut expected);
    let counter = o.map().block("COUNTER").clone();
    let ch = counter.array("CH");
    let word = |offset: u32| counter.base + offset;
    let load = ch.register("CMD").field("LOAD").mask();
    for i in 0..ch.count {
        let writes = [
            (
                word(counter.register("PRESET").offset),
                pattern(i, 0x0123_4567),
            ),
            (word(ch.address(i, "CMD")), load),
            (word(ch.address(i, "CTRL")), pattern(i, 0x7654_3210)),
        ];
        for (w, data) in writes {
            ops.push(Op::Write32 {
                a: (w * 2) as u16,
                data,
            });
            o.write32(w, data);
        }
    }
    // Every PULSE register but RUN (with RUN 0 nothing moves, so every
    // read is predictable): modes, rates, timings, segment staging, and
    // SEG_PUSH five times per axis (the fifth overflows the FIFO).
    let pulse = o.map().block("PULSE").clone();
    let pax = pulse.array("AX");
    for i in 0..pax.count {
        let mut writes: Vec<(u32, u32)> = [
            "CTRL",
            "RATE",
            "STEP_TIMING",
            "DIR_TIMING",
            "SEG_STEPS",
            "SEG_RATE",
            "SEG_ACCEL",
        ]
        .iter()
        .enumerate()
        .map(|(k, r)| {
            (
                pulse.base + pax.address(i, r),
                pattern(i * 16 + k as u32, 0x3c3c_c3c3),
            )
        })
        .collect();
        for _ in 0..=i.min(4) {
            writes.push((pulse.base + pax.address(i, "SEG_PUSH"), 0));
        }
        for (w, data) in writes {
            ops.push(Op::Write32 {
                a: (w * 2) as u16,
                data,
            });
            o.write32(w, data);
        }
    }
    let snapshot = word(counter.register("SNAPSHOT").offset);
    ops.push(Op::Write32 {
        a: (snapshot * 2) as u16,
        data: 0,
    });
    o.write32(snapshot, 0);
    read_all(&o, &mut ops, &mut expected);
    let ram_words = o.ram.len();
    if ram_words == 0 {
        // No RAM window on this bus: its addresses read 0, writes vanish.
        let probes = [0u16, 1, 0x2aa, 0x3ff];
        for (i, k) in probes.iter().enumerate() {
            ops.push(Op::Write16 {
                a: RAM_HALFWORD + k,
                data: 0xA5A5 ^ i as u16,
            });
        }
        for k in probes {
            ops.push(Op::Read16 {
                a: RAM_HALFWORD + k,
            });
            expected.push(0);
        }
        ops.push(Op::Read32 { a: RAM_HALFWORD });
        expected.extend([0, 0]);
    }
    for k in 0..ram_words {
        let data = pattern(k as u32, 0xC0DE_0000) as u16;
        ops.push(Op::Write16 {
            a: RAM_HALFWORD + k as u16,
            data,
        });
        o.ram_write(k, data);
    }
    for k in 0..ram_words {
        ops.push(Op::Read16 {
            a: RAM_HALFWORD + k as u16,
        });
        expected.push(o.ram_read(k));
    }
    // 32-bit accesses to the RAM window: two words, the low one first.
    for k in (0..ram_words.min(64)).step_by(2) {
        let data = pattern(k as u32, 0xBEEF_0000);
        ops.push(Op::Write32 {
            a: RAM_HALFWORD + k as u16,
            data,
        });
        o.ram_write(k, data as u16);
        o.ram_write(k + 1, (data >> 16) as u16);
    }
    for k in (0..ram_words.min(64)).step_by(2) {
        ops.push(Op::Read32 {
            a: RAM_HALFWORD + k as u16,
        });
        expected.extend([o.ram_read(k), o.ram_read(k + 1)]);
    }
    Plan {
        ops,
        expected,
        ignored_writes,
    }
}

/// The pins both top-level builds share with the bench.
pub trait McuTop: Block {
    /// Drives the FSMC pins and reset; the PC side idles (no strobes, AEN
    /// high: a DMA cycle, never ours) and the encoders stay low.
    fn drive(&mut self, p: &FsmcPins, reset: bool);
    /// `fsmc_d_oe` and `fsmc_d_out`.
    fn data(&self) -> (bool, u16);
    fn clock_input(&mut self) -> &mut Signal<In, Clock>;
    /// The loopback wiring: encoder A/B inputs = pulse outputs F1/F2.
    fn feed_back(&mut self);
}

macro_rules! mcu_top {
    ($top:ident) => {
        impl<const N: usize> McuTop for $top<N> {
            fn drive(&mut self, p: &FsmcPins, reset: bool) {
                self.reset.next = reset;
                self.fsmc_ne_n.next = p.ne_n;
                self.fsmc_noe_n.next = p.noe_n;
                self.fsmc_nwe_n.next = p.nwe_n;
                self.fsmc_a.next = u64::from(p.a).into();
                self.fsmc_d_in.next = u64::from(p.d_in).into();
                self.isa_ior_n.next = true;
                self.isa_iow_n.next = true;
                self.isa_aen.next = true;
            }
            fn data(&self) -> (bool, u16) {
                (self.fsmc_d_oe.val(), self.fsmc_d_out.val().index() as u16)
            }
            fn clock_input(&mut self) -> &mut Signal<In, Clock> {
                &mut self.clock
            }
            fn feed_back(&mut self) {
                self.enc_a.next = self.pulse_f1.val();
                self.enc_b.next = self.pulse_f2.val();
            }
        }
    };
}
mcu_top!(MotionController);
mcu_top!(MotionControllerExternal);

/// Steps the rust-hdl top for `config` (either build) through `ops`.
pub fn run_rust<const N: usize>(config: &Config, ops: &[Op]) -> (Vec<Observation>, u64) {
    match config.isa_ram() {
        IsaRam::Internal => run_top(MotionController::<N>::new(config), ops, false),
        IsaRam::External => run_top(MotionControllerExternal::<N>::new(config), ops, false),
    }
}

/// Steps a rust-hdl top through `ops` under the FSMC BFM: what each read
/// observed at the MCU's pins, and the clocks simulated.
/// With `loopback`, the encoder inputs follow the pulse outputs.
pub fn run_top<T: McuTop>(mut uut: T, ops: &[Op], loopback: bool) -> (Vec<Observation>, u64) {
    let (events, end) = timeline(ops, &documented_timing());
    uut.connect_all();
    let mut pins = FsmcPins::idle();
    let mut reset = false;
    let mut observations = Vec::new();
    let mut pending = None;
    let mut clocks = 0;
    let mut edge = FIRST_EDGE_TICKS;
    let mut i = 0;
    while edge <= end || i < events.len() {
        while i < events.len() && events[i].0 < edge {
            match events[i].1 {
                Event::Pins(p, r) => {
                    pins = p;
                    reset = r;
                }
                Event::ObserveSetup | Event::ObserveEnd => {
                    uut.drive(&pins, reset);
                    settle(&mut uut);
                    let now = uut.data();
                    if matches!(events[i].1, Event::ObserveSetup) {
                        pending = Some(now);
                    } else {
                        let (oe_setup, data_setup) = pending.take().expect("setup first");
                        observations.push(Observation {
                            oe_setup,
                            oe_end: now.0,
                            data_setup,
                            data_end: now.1,
                        });
                    }
                }
            }
            i += 1;
        }
        if edge > end {
            break;
        }
        uut.drive(&pins, reset);
        settle(&mut uut);
        if loopback {
            uut.feed_back();
            settle(&mut uut);
        }
        uut.clock_input().next = Clock::from(true);
        settle(&mut uut);
        uut.clock_input().next = Clock::from(false);
        settle(&mut uut);
        clocks += 1;
        edge += CLOCK_TICKS;
    }
    (observations, clocks)
}

/// The top in `target` with an idle PC side (no strobes, AEN high: a DMA
/// cycle, never ours), the encoder inputs low or, with `loopback`, every
/// axis's pulse outputs wired back to its encoder inputs (A = F1, B = F2),
/// and the external RAM build's SRAM and window data buses reading 0.
fn rig(target: Target, config: &Config, loopback: bool) -> Result<Rig, String> {
    let module = catalog::motion_controller(config);
    let mut rig = Rig::new(&module, target.text(&module)?, fsmc::CLOCK);
    let idle_pc: [(&str, u64); 7] = [
        ("isa_sa", 0),
        ("isa_sd_in", 0),
        ("isa_ior_n", 1),
        ("isa_iow_n", 1),
        ("isa_aen", 1),
        ("isa_bale", 0),
        ("isa_base", 0),
    ];
    let mut ties: Vec<(&str, u64)> = idle_pc.to_vec();
    ties.push(("enc_z", 0));
    if loopback {
        rig.loops = vec![
            ("enc_a".into(), "pulse_f1".into()),
            ("enc_b".into(), "pulse_f2".into()),
        ];
    } else {
        ties.extend([("enc_a", 0), ("enc_b", 0)]);
    }
    if config.isa_ram() == IsaRam::External {
        ties.extend([("sram_d_in", 0), ("window_rdata", 0)]);
    }
    rig.ties = ties.into_iter().map(|(n, v)| (n.to_string(), v)).collect();
    rig.sampled = vec!["fsmc_d_oe".into(), "fsmc_d_out".into()];
    Ok(rig)
}

/// The FSMC bus-functional model's stream for `ops` on the top's
/// `fsmc_`-prefixed pins.
fn top_stream(ops: &[Op]) -> PinStream {
    fsmc::stream(ops, &documented_timing()).renamed(|n| match n {
        "reset" => n.to_string(),
        _ => format!("fsmc_{n}"),
    })
}

/// Runs `ops` through the generated `motion_controller.v` in `target`.
pub fn run_verilog(
    target: impl Into<Target>,
    config: &Config,
    ops: &[Op],
) -> Result<Vec<Observation>, String> {
    play(target.into(), config, ops, false)
}

fn play(
    t: Target,
    config: &Config,
    ops: &[Op],
    loopback: bool,
) -> Result<Vec<Observation>, String> {
    t.available()?;
    let samples = rig(t, config, loopback)?.play(t.sim, &top_stream(ops))?;
    fsmc::observations(&samples)
}

/// One case per read halfword: driven from the setup point to the end, with
/// the value the oracle expects.
pub fn compare(name: &str, plan: &Plan, got: &[Observation]) -> CheckReport {
    let mut r = CheckReport::new("motion_controller", name, plan.expected.len() as u64);
    if got.len() != plan.expected.len() {
        r.failures.push(format!(
            "{} reads observed, {} expected",
            got.len(),
            plan.expected.len()
        ));
        return r;
    }
    // Name each read for the failure message.
    let mut names = Vec::new();
    for op in &plan.ops {
        match *op {
            Op::Read16 { a } => names.push(format!("Read16 A={a:#05x}")),
            Op::Read32 { a } => {
                names.push(format!("Read32 A={a:#05x} low"));
                names.push(format!("Read32 A={a:#05x} high"));
            }
            _ => {}
        }
    }
    for (k, (g, want)) in got.iter().zip(&plan.expected).enumerate() {
        let ok = g.oe_setup && g.oe_end && g.data_setup == *want && g.data_end == *want;
        r.case((!ok).then(|| {
            format!(
                "read #{k} ({}): observed {g:?}, expected {want:#06x}",
                names[k]
            )
        }));
    }
    r
}

/// Every register and RAM word of `config`'s top through the Verilog FSMC
/// BFM in `target` (the generated file or its netlist), against the plan.
pub fn check_verilog(target: impl Into<Target>, config: &Config) -> CheckReport {
    let t = target.into();
    let plan = plan(config);
    let label = match t.source {
        Source::Generated => t.sim.name().to_string(),
        _ => t.describe(),
    };
    let name = format!(
        "every register word through FSMC, {} RAM, {label}",
        config.isa_ram().name()
    );
    match run_verilog(t, config, &plan.ops) {
        Ok(obs) => compare(&name, &plan, &obs),
        Err(e) => {
            let r = CheckReport::new("motion_controller", &name, plan.expected.len() as u64);
            if t.available().is_err() {
                r.skip(e)
            } else {
                let mut r = r;
                r.failures.push(e);
                r
            }
        }
    }
}

/// The checks `motionhdl verify` shows for the top (default 4 axes): every
/// register and RAM word through the FSMC pins, both RAM builds, in
/// rust-hdl and with `external` in Icarus and Verilator.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = Vec::new();
    for ram in [IsaRam::Internal, IsaRam::External] {
        let config = Config::default().with_isa_ram(ram);
        let plan = plan(&config);
        v.push(compare(
            &format!(
                "every register word through FSMC, {} RAM, rust-hdl",
                ram.name()
            ),
            &plan,
            &run_rust::<4>(&config, &plan.ops).0,
        ));
        if external {
            for sim in [Simulator::Icarus, Simulator::Verilator] {
                v.push(check_verilog(sim, &config));
            }
        }
    }
    v
}

/// The dual-CPU seed's closed loop on the whole top in the generated
/// Verilog: every axis's pulse outputs wired back to its encoder inputs
/// (A = F1, B = F2) in the testbench, configured and run through the FSMC
/// BFM: axes 0 and 1 pulse+direction (counted PULSE_DIR), axis 2 CW/CCW
/// (counted CW_CCW), axis 3 quadrature (counted X4), rates of both signs
/// with a reversal; then RUN off, SNAPSHOT, and COUNT and POSITION of every
/// axis read over the bus. Returns (COUNT, POSITION) per axis.
pub fn loopback_verilog(
    target: impl Into<Target>,
    config: &Config,
) -> Result<Vec<(i32, i32)>, String> {
    let ops = loopback_ops(config);
    loopback_results(config.axes(), &play(target.into(), config, &ops, true)?)
}

/// The same loop in rust-hdl (default 4 axes, internal RAM).
pub fn loopback_rust(config: &Config) -> Result<Vec<(i32, i32)>, String> {
    let ops = loopback_ops(config);
    let (obs, _) = run_top(MotionController::<4>::new(config), &ops, true);
    loopback_results(config.axes(), &obs)
}

fn loopback_results(n: u32, obs: &[Observation]) -> Result<Vec<(i32, i32)>, String> {
    if obs.len() != 4 * n as usize {
        return Err(format!("{} reads, expected {}", obs.len(), 4 * n));
    }
    let word =
        |k: usize| (u32::from(obs[k].data_end) | u32::from(obs[k + 1].data_end) << 16) as i32;
    Ok((0..n as usize)
        .map(|i| (word(4 * i), word(4 * i + 2)))
        .collect())
}

/// The loopback's FSMC ops: configure, run with a reversal per axis, stop,
/// SNAPSHOT, then COUNT and POSITION of every axis.
pub fn loopback_ops(config: &Config) -> Vec<Op> {
    use motionhdl_model::regmap::mode;
    let map = regmap::mcu_map(config);
    let counter = map.block("COUNTER");
    let pulse = map.block("PULSE");
    let (ch, ax) = (counter.array("CH"), pulse.array("AX"));
    let n = config.axes();
    let w = |word: u32, data: u32| Op::Write32 {
        a: (word * 2) as u16,
        data,
    };
    let mut ops = vec![Op::Reset];
    for i in 0..n {
        let (counter_mode, pulse_ctrl) = match i % 4 {
            0 | 1 => (mode::PULSE_DIR, 0),
            2 => (mode::CW_CCW, 1),
            _ => (mode::X4, 2),
        };
        ops.push(w(counter.base + ch.address(i, "CTRL"), counter_mode));
        ops.push(w(pulse.base + ax.address(i, "CTRL"), pulse_ctrl));
        ops.push(w(
            pulse.base + ax.address(i, "STEP_TIMING"),
            (1 + i % 3) | (1 + i % 2) << 16,
        ));
        ops.push(w(pulse.base + ax.address(i, "DIR_TIMING"), 2 | 2 << 16));
        let rate = 0x1000_0000 * if i % 2 == 0 { 1 } else { -1 };
        ops.push(w(pulse.base + ax.address(i, "RATE"), rate as u32));
    }
    let run = pulse.base + pulse.register("RUN").offset;
    ops.push(w(run, (1 << n) - 1));
    ops.push(Op::Idle { hclk: 3000 });
    for i in 0..n {
        // Reverse every axis at a different moment.
        let rate = -0x0400_0000 * if i % 2 == 0 { 1 } else { -1 };
        ops.push(w(pulse.base + ax.address(i, "RATE"), rate as u32));
        ops.push(Op::Idle { hclk: 200 });
    }
    ops.push(Op::Idle { hclk: 3000 });
    ops.push(w(run, 0));
    ops.push(Op::Idle { hclk: 500 });
    ops.push(w(counter.base + counter.register("SNAPSHOT").offset, 0));
    for i in 0..n {
        ops.push(Op::Read32 {
            a: ((counter.base + ch.address(i, "COUNT")) * 2) as u16,
        });
        ops.push(Op::Read32 {
            a: ((pulse.base + ax.address(i, "POSITION")) * 2) as u16,
        });
    }
    ops
}

/// Segments of [`moves_ops`]: accelerate, cruise, decelerate, and one
/// back (steps, start rate, rate increment per clock).
pub const MOVE_SEGMENTS: [(u32, i32, i32); 4] = [
    (30, 1 << 24, 1 << 20),
    (60, 1 << 28, 0),
    (30, 1 << 28, -(1 << 18)),
    (25, -(1 << 27), 0),
];

/// A position move through axis 0's segment FIFO (MOVES mode), counted by
/// channel 0 in pulse+direction through the pin loopback: stream the four
/// [`MOVE_SEGMENTS`] through the 2-deep FIFO around RUN, wait, then
/// STATUS (DONE, no OVERFLOW), SNAPSHOT, COUNT and POSITION.
pub fn moves_ops(config: &Config) -> Vec<Op> {
    use motionhdl_model::regmap::mode;
    let map = regmap::mcu_map(config);
    let counter = map.block("COUNTER");
    let pulse = map.block("PULSE");
    let (ch, ax) = (counter.array("CH"), pulse.array("AX"));
    let w = |word: u32, data: u32| Op::Write32 {
        a: (word * 2) as u16,
        data,
    };
    let r = |word: u32| Op::Read32 {
        a: (word * 2) as u16,
    };
    let mut ops = vec![
        Op::Reset,
        w(counter.base + ch.address(0, "CTRL"), mode::PULSE_DIR),
        w(pulse.base + ax.address(0, "CTRL"), 0b100),
        w(pulse.base + ax.address(0, "STEP_TIMING"), 2 | 2 << 16),
        w(pulse.base + ax.address(0, "DIR_TIMING"), 3 | 3 << 16),
    ];
    let push = |ops: &mut Vec<Op>, (steps, rate, accel): (u32, i32, i32)| {
        ops.push(w(pulse.base + ax.address(0, "SEG_STEPS"), steps));
        ops.push(w(pulse.base + ax.address(0, "SEG_RATE"), rate as u32));
        ops.push(w(pulse.base + ax.address(0, "SEG_ACCEL"), accel as u32));
        ops.push(w(pulse.base + ax.address(0, "SEG_PUSH"), 0));
    };
    // The FIFO holds two: fill it, start, and top it up as the firmware
    // would. Segment 0 (about 480 clocks) has ended before the 4000-HCLK
    // (1190-clock) wait is over, so the last push finds room.
    let [s0, s1, s2, s3] = MOVE_SEGMENTS;
    push(&mut ops, s0);
    push(&mut ops, s1);
    ops.push(w(pulse.base + pulse.register("RUN").offset, 1));
    push(&mut ops, s2);
    ops.push(Op::Idle { hclk: 4000 });
    push(&mut ops, s3);
    for _ in 0..8 {
        ops.push(Op::Idle { hclk: 4000 });
    }
    ops.push(r(pulse.base + ax.address(0, "STATUS")));
    ops.push(w(counter.base + counter.register("SNAPSHOT").offset, 0));
    ops.push(r(counter.base + ch.address(0, "COUNT")));
    ops.push(r(pulse.base + ax.address(0, "POSITION")));
    ops
}

/// (STATUS, COUNT, POSITION) the reads of [`moves_ops`] returned.
fn moves_results(obs: &[Observation]) -> Result<(u32, i32, i32), String> {
    if obs.len() != 6 {
        return Err(format!("{} reads, expected 6", obs.len()));
    }
    let word = |k: usize| u32::from(obs[k].data_end) | u32::from(obs[k + 1].data_end) << 16;
    Ok((word(0), word(2) as i32, word(4) as i32))
}

/// [`moves_ops`] in rust-hdl with the pin loopback.
pub fn moves_rust(config: &Config) -> Result<(u32, i32, i32), String> {
    let (obs, _) = run_top(MotionController::<4>::new(config), &moves_ops(config), true);
    moves_results(&obs)
}

/// [`moves_ops`] in the generated Verilog with the pin loopback.
pub fn moves_verilog(
    target: impl Into<Target>,
    config: &Config,
) -> Result<(u32, i32, i32), String> {
    moves_results(&play(target.into(), config, &moves_ops(config), true)?)
}
