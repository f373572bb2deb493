//! The oracle of the top-level bus checks: what the MCU must read, from
//! the register-map table, the counter bank and pulse generator models and
//! a RAM array; and the plan of ops that reads and writes every word.

use crate::bfm::fsmc::Op;
use motionhdl_model::counter::{Bank, BusCycle, CounterParams};
use motionhdl_model::pulse_generator::PulseBank;
use motionhdl_model::regmap::{self, Access, BusMap, ERR_COUNT_BITS};
use motionhdl_model::safety_io::SafetyIo;
use motionhdl_model::servo_dac::ServoDac;
use motionhdl_model::Config;

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
    safety: SafetyIo,
    servo: Option<ServoDac>,
    axes: usize,
    ram: Vec<u16>,
}

impl McuOracle {
    pub fn new(config: &Config) -> Self {
        let map = regmap::mcu_map(config);
        let bank = Bank::new(
            config.axes(),
            CounterParams::new(config.counter_width(), ERR_COUNT_BITS)
                .with_features(config.counter_features()),
        );
        let words = map.memories.first().map_or(0, |m| m.words) as usize;
        Self {
            map,
            bank,
            pulses: PulseBank::new(config.axes(), config.counter_width()),
            safety: SafetyIo::new(config.axes(), config.filter_tick_clocks()),
            servo: config.servo_dac().then(|| ServoDac::new(config.clock_hz())),
            axes: config.axes() as usize,
            ram: vec![0; words],
        }
    }

    pub fn map(&self) -> &BusMap {
        &self.map
    }

    /// One clock of the counter bank (bus `bus`), the pulse bank (bus
    /// `pulse_bus`), the safety block (idle bus, the e-stop chain closed)
    /// and the SERVO block if any (bus `servo_bus`); the counter's
    /// SNAPSHOT and the servo tick also capture the pulses.
    fn clock_all(
        &mut self,
        reset: bool,
        bus: &BusCycle,
        (pulse_bus, servo_bus): (&BusCycle, &BusCycle),
    ) {
        let pins = vec![(false, false, false); self.axes];
        let counter = self.map.block("COUNTER");
        let tick = self.servo.as_ref().is_some_and(ServoDac::tick);
        let halt = self.safety.halted();
        let snapshot = bus.we && bus.addr == counter.register("SNAPSHOT").offset || tick;
        let flags = self.bank.flags();
        self.bank.clock_strobed(&pins, reset, bus, (0, tick));
        self.safety.clock_with_pulses(
            &mut self.pulses,
            reset,
            (pulse_bus, snapshot),
            &BusCycle::default(),
            (true, Default::default()),
            (flags.0, flags.1, false, tick),
        );
        if let Some(servo) = &mut self.servo {
            servo.clock(reset, servo_bus, halt);
        }
    }

    fn clock_bank(&mut self, reset: bool, bus: &BusCycle) {
        let idle = BusCycle::default();
        self.clock_all(reset, bus, (&idle, &idle));
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
            Some((block @ ("COUNTER" | "PULSE" | "SAFETY" | "SERVO"), offset)) => self
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
                self.clock_all(false, &BusCycle::write(offset, data), (&idle, &idle))
            }
            Some(("PULSE", offset)) => {
                self.clock_all(false, &idle, (&BusCycle::write(offset, data), &idle))
            }
            Some(("SERVO", offset)) => {
                self.clock_all(false, &idle, (&idle, &BusCycle::write(offset, data)))
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
            Some(("SAFETY", offset)) => self.safety.read_value(offset),
            Some(("SERVO", offset)) => self
                .servo
                .as_ref()
                .expect("SERVO in the map")
                .read_value(offset),
            Some((other, _)) => panic!("oracle has no model of block {other}"),
            None => 0,
        }
    }
}

/// The SERVO writes of the plan: short TIMING (so a transfer ends within
/// the oracle's settling clocks), a code per channel, UPDATE (one
/// transfer: OUTPUT reads the codes back), a TICK_PERIOD too long to end
/// within the run (a tick's snapshot would move nothing here, but its
/// clock is the bus's, not the oracle's), and EVENTS cleared.
fn servo_writes(servo: &regmap::Block) -> Vec<(u32, u32)> {
    let word = |name: &str| servo.base + servo.register(name).offset;
    let ch = servo.array("CH");
    let mut writes = vec![(word("TIMING"), 0x0201)];
    for i in 0..ch.count {
        writes.push((servo.base + ch.address(i, "CODE"), pattern(i, 0x1357_9bdf)));
    }
    writes.push((word("UPDATE"), 1));
    writes.push((word("TICK_PERIOD"), pattern(7, 0) | 0x4000_0000));
    writes.push((word("EVENTS"), 3));
    writes
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

/// 32-bit writes of (register word, data), into the plan's ops and the
/// oracle.
fn write_all(o: &mut McuOracle, ops: &mut Vec<Op>, writes: impl IntoIterator<Item = (u32, u32)>) {
    for (w, data) in writes {
        ops.push(Op::Write32 {
            a: (w * 2) as u16,
            data,
        });
        o.write32(w, data);
    }
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
        write_all(&mut o, &mut ops, writes);
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
            "SEG_JERK",
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
        write_all(&mut o, &mut ops, writes);
    }
    if o.map().blocks.iter().any(|b| b.name == "SERVO") {
        let writes = servo_writes(o.map().block("SERVO"));
        write_all(&mut o, &mut ops, writes);
    }
    let snapshot = word(counter.register("SNAPSHOT").offset);
    write_all(&mut o, &mut ops, [(snapshot, 0)]);
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
    ram_window_ops(&mut o.ram, &mut ops, &mut expected);
    Plan {
        ops,
        expected,
        ignored_writes,
    }
}

/// The RAM window's part of a plan: every word of `ram` written with a
/// pattern and read back as 16-bit accesses, then the first 64 words
/// written and read as 32-bit pairs (the low word first). `ram` follows
/// the writes; each read's halfwords go to `expected`.
pub fn ram_window_ops(ram: &mut [u16], ops: &mut Vec<Op>, expected: &mut Vec<u16>) {
    let words = ram.len();
    for (k, word) in ram.iter_mut().enumerate() {
        let data = pattern(k as u32, 0xC0DE_0000) as u16;
        ops.push(Op::Write16 {
            a: RAM_HALFWORD + k as u16,
            data,
        });
        *word = data;
    }
    for (k, word) in ram.iter().enumerate() {
        ops.push(Op::Read16 {
            a: RAM_HALFWORD + k as u16,
        });
        expected.push(*word);
    }
    // 32-bit accesses to the RAM window: two words, the low one first.
    for k in (0..words.min(64)).step_by(2) {
        let data = pattern(k as u32, 0xBEEF_0000);
        ops.push(Op::Write32 {
            a: RAM_HALFWORD + k as u16,
            data,
        });
        ram[k] = data as u16;
        ram[k + 1] = (data >> 16) as u16;
    }
    for k in (0..words.min(64)).step_by(2) {
        ops.push(Op::Read32 {
            a: RAM_HALFWORD + k as u16,
        });
        expected.extend([ram[k], ram[k + 1]]);
    }
}
