//! The top against docs/motion_controller.md: the MCU's address map through
//! the FSMC pins, the wiring between the blocks (RAM window, encoders,
//! pulse pins, SNAPSHOT, e-stop) and the model's own API.

use super::*;
use crate::regmap::BusMap;

/// FPGA clocks of the FSMC waveform (docs/fsmc_bridge.md: ADDSET 4 and
/// DATAST 21 HCLKs are at least one and six clocks at 50 MHz).
const ADDSET_CLOCKS: usize = 1;
const DATAST_CLOCKS: usize = 6;
const IDLE_CLOCKS: usize = 4;

struct Top {
    m: MotionControllerModel,
    map: BusMap,
    inp: TopInputs,
    /// Every output seen, one per clock.
    seen: Vec<TopOutputs>,
}

impl Top {
    /// After a four-clock reset (the e-stop latch is then set).
    fn new(config: &Config) -> Self {
        let mut t = Self {
            m: MotionControllerModel::new(config),
            map: regmap::mcu_map(config),
            inp: TopInputs::idle(),
            seen: Vec::new(),
        };
        t.inp.reset = true;
        t.steps(4);
        t.inp.reset = false;
        t.steps(2);
        t
    }

    fn step(&mut self) -> TopOutputs {
        let out = self.m.step(&self.inp);
        self.seen.push(out);
        out
    }

    fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Register word address of `block`'s `register`.
    fn word(&self, block: &str, register: &str) -> u16 {
        let b = self.map.block(block);
        (b.base + b.register(register).offset) as u16
    }

    /// Register word address of register `register` of `array[i]`.
    fn array_word(&self, block: &str, array: &str, i: u32, register: &str) -> u16 {
        let b = self.map.block(block);
        (b.base + b.array(array).address(i, register)) as u16
    }

    /// One FSMC access of halfword `a` in mode 1; NE1# stays low when
    /// `more` follows. Returns the data a read samples.
    fn half(&mut self, a: u16, write: Option<u16>, more: bool) -> u16 {
        self.inp.fsmc_ne_n = false;
        self.inp.fsmc_a = a;
        self.inp.fsmc_d_in = !write.unwrap_or(0);
        self.steps(ADDSET_CLOCKS);
        let mut data = 0;
        for k in 0..DATAST_CLOCKS {
            match write {
                Some(d) => {
                    self.inp.fsmc_nwe_n = false;
                    self.inp.fsmc_d_in = if k == 0 { !d } else { d };
                }
                None => self.inp.fsmc_noe_n = false,
            }
            let out = self.step();
            assert!(out.fsmc_d_oe == write.is_none(), "d_oe at {a:#x}");
            data = out.fsmc_d_out;
        }
        self.inp.fsmc_noe_n = true;
        self.inp.fsmc_nwe_n = true;
        if !more {
            self.inp.fsmc_ne_n = true;
            self.inp.fsmc_a = 0;
            self.steps(IDLE_CLOCKS);
        }
        data
    }

    fn read32(&mut self, word: u16) -> u32 {
        let lo = self.half(word * 2, None, true);
        let hi = self.half(word * 2 + 1, None, false);
        u32::from(hi) << 16 | u32::from(lo)
    }

    fn write32(&mut self, word: u16, v: u32) {
        self.half(word * 2, Some(v as u16), true);
        self.half(word * 2 + 1, Some((v >> 16) as u16), false);
    }

    /// SAFETY.CLEAR.ESTOP = 1 with `estop_ok` high, as every check does
    /// after its reset.
    fn clear_estop(&mut self) {
        let clear = self.word("SAFETY", "CLEAR");
        self.write32(clear, 1);
        assert!(!self.m.safety().halted());
    }

    /// What word `w` of the MCU map should read now, from the address
    /// table of docs/motion_controller.md and the block that owns it.
    fn expected(&self, w: u16) -> u32 {
        let w = u32::from(w);
        match w * 4 {
            0x0000..=0x003f => {
                let id = self.map.block("ID");
                id.registers
                    .iter()
                    .find(|r| r.offset == w)
                    .map_or(0, |r| r.reset)
            }
            0x0040..=0x007f => self.m.servo().map_or(0, |s| s.read_value(w & 0xf)),
            0x0200..=0x03ff => self.m.safety().read_value(w & 0x7f),
            0x0400..=0x07ff => self.m.counters().read_value(w & 0xff),
            0x0800..=0x0fff => self.m.pulses().read_value(w & 0x1ff),
            _ => 0,
        }
    }
}

fn three_axes() -> Config {
    Config::default().with_axes(3).unwrap()
}

#[test]
fn every_register_word_reads_what_its_block_holds() {
    for config in [
        three_axes(),
        Config::default().with_servo_dac(true).with_axes(2).unwrap(),
    ] {
        let mut t = Top::new(&config);
        assert_eq!(t.m.servo().is_some(), config.servo_dac());
        let mut nonzero = 0;
        for w in 0..1024u16 {
            let expected = t.expected(w);
            let got = t.read32(w);
            assert_eq!(
                got,
                expected,
                "word {w:#05x} (byte {:#06x}), {config:?}",
                w * 4
            );
            nonzero += usize::from(got != 0);
        }
        // The ID block's constants and every block's INFO at least.
        assert!(nonzero >= 12, "{nonzero} non-zero words, {config:?}");
    }
}

#[test]
fn writes_reach_only_the_addressed_register() {
    let config = Config::default().with_servo_dac(true).with_axes(2).unwrap();
    let mut t = Top::new(&config);
    let targets = [
        t.word("COUNTER", "PRESET"),
        t.array_word("PULSE", "AX", 1, "RATE"),
        t.word("SAFETY", "LIMIT_MASK"),
        t.word("SERVO", "PREFIX"),
    ];
    // Distinct values that fit each register (LIMIT_MASK: 2 axes per half).
    let values = [0x0003_0001, 0x0006_0002, 0x0002_0001, 0x0018_0008];
    let before: Vec<u32> = (0..1024).map(|w| t.expected(w)).collect();
    for (k, &w) in targets.iter().enumerate() {
        t.write32(w, values[k]);
    }
    // Last, a write that lands nowhere (ID is read-only): its data stays on
    // the register port's write data while the targets are read back.
    t.write32(t.word("ID", "MAGIC"), 0xffff_ffff);
    for (k, &w) in targets.iter().enumerate() {
        assert_eq!(t.read32(w), values[k], "word {w:#x}");
    }
    // SERVO.STATUS is live (its transfers run on their own).
    let live = t.word("SERVO", "STATUS");
    let changed: Vec<u16> = (0..1024)
        .filter(|&w| w != live)
        .filter(|&w| t.expected(w) != before[usize::from(w)])
        .collect();
    let mut targets_sorted = targets.to_vec();
    targets_sorted.sort();
    assert_eq!(changed, targets_sorted);
}

#[test]
fn ram_window_is_the_isa_bridges_ram() {
    let mut t = Top::new(&three_axes());
    // (halfword address, RAM word): A10 is not decoded.
    let cases = [
        (0x800u16, 0usize, 0x1234u16),
        (0xbff, 0x3ff, 0xfedc),
        (0xc05, 5, 0x0505),
    ];
    for (a, word, v) in cases {
        t.half(a, Some(v), false);
        assert_eq!(t.m.isa().ram()[word], v, "write at {a:#x}");
    }
    assert_eq!(cases.len(), 3);
    for (a, _, v) in cases {
        assert_eq!(t.half(a ^ 0x400, None, false), v, "mirror of {a:#x}");
    }
    // A RAM access is no register access: the kept half survives nothing.
    let magic = t.word("ID", "MAGIC");
    t.half(magic * 2, None, false);
    assert_eq!(t.m.fsmc().hold().map(|h| h.0), Some(magic), "low half kept");
}

#[test]
fn isa_card_select_ignores_bits_above_sa9() {
    let mut t = Top::new(&three_axes());
    t.inp.isa_base = 0x42;
    // (SA pins, card selected: IOCS16# pulled low)
    let cases = [
        (0x108u16, true),
        (0xfd0b, true),
        (0x10c, false),
        (0x308, false),
    ];
    for (sa, selected) in cases {
        t.inp.isa_sa = sa;
        let out = t.m.outputs(&t.inp);
        assert_eq!(out.isa_iocs16_n, !selected, "SA = {sa:#06x}, base 0x42");
    }
    assert_eq!(cases.len(), 4);
}

#[test]
fn each_encoder_pin_counts_its_own_channel() {
    let mut t = Top::new(&three_axes());
    // Quadrature A/B: axis 0 forward 8 counts, axis 1 back 4, axis 2 still
    // with A and B high. Z of axis 1 rises at count -2 and falls at -4:
    // the index latches on the rise, on channel 1 alone.
    for ch in 0..2 {
        let ctrl = t.array_word("COUNTER", "CH", ch, "CTRL");
        t.write32(ctrl, 1 << 6); // IDX_LATCH
    }
    let phase = |p: i32| crate::pulse_generator::quadrature(p as u32);
    t.inp.enc_a = 0b100;
    t.inp.enc_b = 0b100;
    t.steps(20);
    for k in 1..=8 {
        let (a0, b0) = phase(k);
        let (a1, b1) = phase(-k.min(4));
        t.inp.enc_a = 0b100 | u16::from(a1) << 1 | u16::from(a0);
        t.inp.enc_b = 0b100 | u16::from(b1) << 1 | u16::from(b0);
        t.steps(20);
        if k == 2 {
            t.inp.enc_z = 0b010;
            t.steps(20);
        }
    }
    t.inp.enc_z = 0;
    t.steps(20);
    let state = |t: &Top, i: usize| {
        let s = t.m.counters().channel(i).state();
        (s.count, s.index)
    };
    let width_mask = (1u32 << 28) - 1;
    assert_eq!(state(&t, 0), (8, 0), "axis 0");
    assert_eq!(state(&t, 1), (width_mask - 3, width_mask - 1), "axis 1");
    assert_eq!(state(&t, 2), (0, 0), "axis 2");
}

#[test]
fn pulse_pins_snapshot_and_e_stop() {
    let mut t = Top::new(&three_axes());
    t.clear_estop();
    let rate = |t: &Top, i| t.array_word("PULSE", "AX", i, "RATE");
    let position = |t: &Top, i| t.array_word("PULSE", "AX", i, "POSITION");
    t.write32(rate(&t, 1), (-(1i32 << 29)) as u32);
    t.write32(rate(&t, 2), 1 << 28);
    t.write32(t.word("SAFETY", "ENABLE"), 0b111);
    t.write32(t.word("PULSE", "RUN"), 0b110);
    let from = t.seen.len();
    t.steps(200);
    t.write32(t.word("PULSE", "RUN"), 0);
    t.steps(50);
    let seen = &t.seen[from..];
    let rises = |bit: u16, f2: bool| {
        seen.windows(2)
            .filter(|w| {
                let pin = |o: &TopOutputs| (if f2 { o.pulse_f2 } else { o.pulse_f1 }) >> bit & 1;
                pin(&w[0]) == 0 && pin(&w[1]) == 1
            })
            .count() as u32
    };
    let (steps1, steps2) = (rises(1, false), rises(2, false));
    assert!(
        steps1 > 10 && steps2 > 5,
        "axis 1: {steps1}, axis 2: {steps2}"
    );
    assert_eq!(
        rises(0, false) + rises(0, true) + rises(2, true),
        0,
        "axis 0 still, axis 2 up"
    );
    assert_eq!(rises(1, true), 1, "axis 1's direction pin: negative");
    assert!(seen
        .iter()
        .all(|o| o.pulse_f1 & !0b110 == 0 && o.drive_enable == 0b111));
    // SNAPSHOT captures the pulse positions too; other counter writes do not.
    t.write32(t.word("COUNTER", "SNAPSHOT"), 1);
    assert_eq!(t.read32(position(&t, 1)), steps1.wrapping_neg());
    assert_eq!(t.read32(position(&t, 2)), steps2);
    t.write32(t.word("PULSE", "RUN"), 0b100);
    t.steps(100);
    t.write32(t.word("COUNTER", "PRESET"), 1);
    assert_eq!(t.read32(position(&t, 2)), steps2, "PRESET is no SNAPSHOT");
    // The e-stop chain opens at edge k: drive_enable low from edge k + 2, no
    // step edge after edge k + 4.
    let k = t.seen.len();
    t.inp.estop_ok = false;
    t.steps(40);
    let enables: Vec<u16> = t.seen[k..k + 4].iter().map(|o| o.drive_enable).collect();
    assert_eq!(
        enables,
        [0b111, 0b111, 0b111, 0],
        "outputs before edges k..k+3"
    );
    let f1_after: Vec<u16> = t.seen[k + 5..].iter().map(|o| o.pulse_f1).collect();
    assert!(f1_after.windows(2).all(|w| w[0] == w[1]), "{f1_after:?}");
    assert!(t.m.safety().halted());
}

#[test]
fn step_is_outputs_then_clock() {
    let config = three_axes();
    let mut a = MotionControllerModel::new(&config);
    let mut b = MotionControllerModel::new(&config);
    let mut last = TopOutputs::default();
    for k in 0..30 {
        // A reset, then a low-half read of ID.MAGIC.
        let mut inp = TopInputs::idle();
        inp.reset = k < 4;
        inp.fsmc_ne_n = k < 10;
        inp.fsmc_noe_n = k < 12;
        let expected = b.outputs(&inp);
        b.clock(&inp);
        last = a.step(&inp);
        assert_eq!(last, expected, "clock {k}");
    }
    assert_eq!(
        (last.fsmc_d_oe, last.fsmc_d_out),
        (true, 0x444c),
        "MAGIC's low half"
    );
}

#[test]
fn pins_lists_every_output_once() {
    let out = TopOutputs {
        fsmc_d_out: 101,
        fsmc_d_oe: true,
        isa_sd_out: 102,
        isa_sd_oe: true,
        isa_iocs16_n: true,
        isa_irq: true,
        pulse_f1: 103,
        pulse_f2: 104,
        drive_enable: 105,
        irq: true,
        gpo_out: 106,
        gpo_oe: 107,
        dac_data: 108,
        dac_addr: 109,
        dac_cs_n: true,
        dac_rw_n: true,
        dac_ldac_n: true,
        dac_sclk: true,
        dac_sdin: true,
        dac_sync_n: true,
    };
    let pins = out.pins();
    let mut names: Vec<&str> = pins.iter().map(|p| p.0).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), 20, "{pins:?}");
    let value = |name: &str| pins.iter().find(|p| p.0 == name).unwrap().1;
    assert_eq!(value("fsmc_d_out"), 101);
    assert_eq!(value("gpo_oe"), 107);
    assert_eq!(value("dac_addr"), 109);
    assert_eq!(value("irq"), 1);
    // 101..=109 and eleven pins at 1.
    assert_eq!(pins.iter().map(|p| p.1).sum::<u32>(), 945 + 11);
}

#[test]
fn axes_and_axis_mask_follow_the_config() {
    for axes in [1u32, 3, 16] {
        let m = MotionControllerModel::new(&Config::default().with_axes(u64::from(axes)).unwrap());
        assert_eq!(m.axes(), axes as usize, "axes = {axes}");
        assert_eq!(u32::from(m.axis_mask()), (1 << axes) - 1, "axes = {axes}");
    }
}
