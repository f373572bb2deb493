//! The driver against a fake bus that knows the register table (the spec
//! crate's, not the generated module the driver uses) and records every
//! access by name: each call makes the documented accesses, in order, and
//! touches nothing it should not.

use motionhdl_driver::{AxisConfig, AxisSample, Bus, Card, Causes, Error, Segment, Stream, AXES};
use motionhdl_spec::regmap::{self, Access, BusMap};
use motionhdl_spec::safety_io::WATCHDOG_KEY;
use motionhdl_spec::Config;
use std::collections::HashMap;

/// Registers by byte offset: ("BLOCK.REG" or "BLOCK.ARR[i].REG", access).
struct FakeCard {
    names: HashMap<u32, (String, Access)>,
    map: BusMap,
    values: HashMap<u32, u32>,
    ram: Vec<u16>,
    log: Vec<String>,
}

impl FakeCard {
    fn new() -> Self {
        let map = regmap::mcu_map(&Config::default());
        let mut names = HashMap::new();
        let mut values = HashMap::new();
        for b in &map.blocks {
            for (word, r, i) in b.decoded() {
                let name = match i {
                    Some(i) => {
                        let array = b.arrays.iter().find(|a| a.registers.contains(r)).unwrap();
                        format!("{}.{}[{i}].{}", b.name, array.name, r.name)
                    }
                    None => format!("{}.{}", b.name, r.name),
                };
                let offset = (b.base + word) * 4;
                names.insert(offset, (name, r.access));
                values.insert(offset, r.reset);
            }
        }
        let ram = vec![0; map.memories[0].words as usize];
        Self {
            names,
            map,
            values,
            ram,
            log: Vec::new(),
        }
    }

    fn offset(&self, name: &str) -> u32 {
        *self
            .names
            .iter()
            .find(|(_, (n, _))| n == name)
            .unwrap_or_else(|| panic!("no {name}"))
            .0
    }

    fn set(&mut self, name: &str, value: u32) {
        let o = self.offset(name);
        self.values.insert(o, value);
    }

    fn field(&self, block: &str, reg: &str, field: &str, value: u32) -> u32 {
        let b = self.map.block(block);
        let r = b.registers.iter().find(|r| r.name == reg);
        let r = r.unwrap_or_else(|| b.arrays[0].register(reg));
        r.field(field).get(value)
    }

    fn take_log(&mut self) -> Vec<String> {
        std::mem::take(&mut self.log)
    }

    fn register(&self, offset: u32) -> (String, Access) {
        self.names
            .get(&offset)
            .cloned()
            .unwrap_or_else(|| panic!("access to 0x{offset:04x}: no register there"))
    }

    fn ram_word(&self, offset: u32) -> usize {
        let m = &self.map.memories[0];
        assert!(
            offset.is_multiple_of(2) && offset >= m.byte_offset,
            "RAM access at 0x{offset:x}"
        );
        let w = ((offset - m.byte_offset) / 2) as usize;
        assert!(w < self.ram.len(), "RAM word {w} beyond the window");
        w
    }
}

impl Bus for FakeCard {
    fn read32(&mut self, offset: u32) -> u32 {
        let (name, access) = self.register(offset);
        assert_ne!(access, Access::WriteOnly, "read of write-only {name}");
        self.log.push(format!("R {name}"));
        self.values[&offset]
    }
    fn write32(&mut self, offset: u32, value: u32) {
        let (name, access) = self.register(offset);
        assert_ne!(access, Access::ReadOnly, "write of read-only {name}");
        self.log.push(format!("W {name} 0x{value:x}"));
        self.values.insert(offset, value);
    }
    fn read16(&mut self, offset: u32) -> u16 {
        let w = self.ram_word(offset);
        self.log.push(format!("R RAM[{w}]"));
        self.ram[w]
    }
    fn write16(&mut self, offset: u32, value: u16) {
        let w = self.ram_word(offset);
        self.log.push(format!("W RAM[{w}] 0x{value:x}"));
        self.ram[w] = value;
    }
}

fn card() -> Card<FakeCard> {
    Card::new(FakeCard::new())
}

fn log(c: &mut Card<FakeCard>) -> Vec<String> {
    c.bus().take_log()
}

#[test]
fn the_driver_is_built_for_the_default_map() {
    let map = regmap::mcu_map(&Config::default());
    assert_eq!(motionhdl_driver::regs::MAP_HASH, regmap::map_hash(&map));
    assert_eq!(AXES, Config::default().axes());
}

#[test]
fn check_accepts_its_card_and_names_each_mismatch() {
    let mut c = card();
    let version = c.bus().values[&4];
    assert_eq!(c.check(), Ok(version));
    assert_eq!(log(&mut c), ["R ID.MAGIC", "R ID.VERSION", "R ID.MAP_HASH"]);
    c.bus().set("ID.MAGIC", 0xffff_ffff);
    assert_eq!(c.check(), Err(Error::Magic(0xffff_ffff)));
    assert_eq!(log(&mut c), ["R ID.MAGIC"], "stops at the first mismatch");
    let mut c = card();
    c.bus().set("ID.VERSION", version + (1 << 16));
    assert_eq!(c.check(), Err(Error::Version(version + (1 << 16))));
    let mut c = card();
    c.bus().set("ID.VERSION", version + 1);
    assert_eq!(c.check(), Ok(version + 1), "a newer patch or minor is fine");
    c.bus().set("ID.MAP_HASH", 0x1234_5678);
    assert_eq!(c.check(), Err(Error::MapHash(0x1234_5678)));
}

#[test]
fn sample_takes_one_snapshot_then_reads_every_axis() {
    let mut c = card();
    for i in 0..AXES {
        c.bus()
            .set(&format!("COUNTER.CH[{i}].COUNT"), (-(i as i32) - 5) as u32);
        c.bus().set(&format!("PULSE.AX[{i}].POSITION"), 100 + i);
    }
    let mut out = [AxisSample::default(); 4];
    c.sample(&mut out).unwrap();
    let mut want = vec!["W COUNTER.SNAPSHOT 0x0".to_string()];
    for i in 0..AXES {
        for r in [
            "COUNTER.CH[{i}].COUNT",
            "COUNTER.CH[{i}].INDEX",
            "COUNTER.CH[{i}].STATUS",
            "PULSE.AX[{i}].POSITION",
        ] {
            want.push(format!("R {}", r.replace("{i}", &i.to_string())));
        }
        assert_eq!(out[i as usize].count, -(i as i32) - 5);
        assert_eq!(out[i as usize].position, 100 + i as i32);
    }
    assert_eq!(log(&mut c), want);
    let mut five = [AxisSample::default(); 5];
    assert_eq!(c.sample(&mut five), Err(Error::Argument));
    assert!(log(&mut c).is_empty());
}

#[test]
fn a_segment_is_four_words_then_a_push() {
    let mut c = card();
    let seg = Segment {
        steps: 7,
        rate: -3,
        accel: 5,
        jerk: -9,
    };
    c.push_segment(2, &seg).unwrap();
    assert_eq!(
        log(&mut c),
        [
            "W PULSE.AX[2].SEG_STEPS 0x7",
            "W PULSE.AX[2].SEG_RATE 0xfffffffd",
            "W PULSE.AX[2].SEG_ACCEL 0x5",
            "W PULSE.AX[2].SEG_JERK 0xfffffff7",
            "W PULSE.AX[2].SEG_PUSH 0x0",
        ]
    );
}

#[test]
fn refill_pushes_what_the_fifo_has_room_for() {
    let mut c = card();
    let segs: Vec<Segment> = (1..=10)
        .map(|k| Segment {
            steps: k,
            rate: 1 << 28,
            accel: 0,
            jerk: 0,
        })
        .collect();
    let level = |v: u32| v << 20;
    c.bus().set("PULSE.AX[1].STATUS", level(60));
    let mut s = Stream::new(1);
    assert_eq!(s.refill(&mut c, &segs), Ok(false));
    assert_eq!(s.next, 4);
    let l = log(&mut c);
    assert_eq!(l[0], "R PULSE.AX[1].STATUS");
    assert_eq!(l.iter().filter(|e| e.contains("SEG_PUSH")).count(), 4);
    assert_eq!(l[1], "W PULSE.AX[1].SEG_STEPS 0x1");
    c.bus().set("PULSE.AX[1].STATUS", level(0));
    assert_eq!(s.refill(&mut c, &segs), Ok(true));
    assert_eq!(s.next, 10);
    assert_eq!(log(&mut c)[1], "W PULSE.AX[1].SEG_STEPS 0x5");
    c.bus().set("PULSE.AX[1].STATUS", 1 << 19);
    assert_eq!(s.refill(&mut c, &segs), Err(Error::FifoOverflow(1)));
}

#[test]
fn an_axis_is_set_up_field_by_field() {
    let mut c = card();
    let cfg = AxisConfig {
        cw_ccw: 1,
        quadrature: 0,
        step_len: 3,
        step_space: 4,
        dir_setup: 5,
        dir_hold: 6,
        fifo_low_water: 16,
        decel: 77,
    };
    c.axis_configure(3, &cfg).unwrap();
    let l = log(&mut c);
    let names: Vec<&str> = l.iter().map(|e| e.split(' ').nth(1).unwrap()).collect();
    assert_eq!(
        names,
        [
            "PULSE.AX[3].CTRL",
            "PULSE.AX[3].STEP_TIMING",
            "PULSE.AX[3].DIR_TIMING",
            "PULSE.AX[3].FIFO_LOW_WATER",
            "PULSE.AX[3].DECEL"
        ]
    );
    let b = c.bus();
    let v = |n: &str| b.values[&b.offset(n)];
    let ctrl = v("PULSE.AX[3].CTRL");
    assert_eq!(b.field("PULSE", "CTRL", "MODE", ctrl), 1);
    assert_eq!(b.field("PULSE", "CTRL", "MOVES", ctrl), 1);
    assert_eq!(b.field("PULSE", "CTRL", "QUADRATURE", ctrl), 0);
    let st = v("PULSE.AX[3].STEP_TIMING");
    assert_eq!(
        (
            b.field("PULSE", "STEP_TIMING", "STEP_LEN", st),
            b.field("PULSE", "STEP_TIMING", "STEP_SPACE", st)
        ),
        (3, 4)
    );
    let dt = v("PULSE.AX[3].DIR_TIMING");
    assert_eq!(
        (
            b.field("PULSE", "DIR_TIMING", "DIR_SETUP", dt),
            b.field("PULSE", "DIR_TIMING", "DIR_HOLD", dt)
        ),
        (5, 6)
    );
    assert_eq!(v("PULSE.AX[3].FIFO_LOW_WATER"), 16);
    assert_eq!(v("PULSE.AX[3].DECEL"), 77);
    let bad = AxisConfig {
        fifo_low_water: 65,
        ..cfg
    };
    assert_eq!(c.axis_configure(0, &bad), Err(Error::Argument));
    assert!(log(&mut c).is_empty());
}

#[test]
fn start_and_stop_are_one_run_write_each() {
    let mut c = card();
    c.bus().set("PULSE.RUN", 0b0001);
    c.start(0b0110).unwrap();
    assert_eq!(log(&mut c), ["R PULSE.RUN", "W PULSE.RUN 0x7"]);
    c.stop(0b0011).unwrap();
    assert_eq!(log(&mut c), ["R PULSE.RUN", "W PULSE.RUN 0x4"]);
    assert_eq!(c.start(1 << AXES), Err(Error::Argument));
    assert!(log(&mut c).is_empty());
}

#[test]
fn every_axis_call_refuses_an_axis_the_card_lacks() {
    let mut c = card();
    let seg = Segment::default();
    assert_eq!(c.counter_configure(AXES, 0), Err(Error::Argument));
    assert_eq!(c.counter_load(AXES, 0), Err(Error::Argument));
    assert_eq!(c.counter_command(AXES, 0), Err(Error::Argument));
    assert_eq!(
        c.axis_configure(AXES, &AxisConfig::default()),
        Err(Error::Argument)
    );
    assert_eq!(c.axis_status(AXES), Err(Error::Argument));
    assert_eq!(c.push_segment(AXES, &seg), Err(Error::Argument));
    assert_eq!(
        Stream::new(AXES).refill(&mut c, &[seg]),
        Err(Error::Argument)
    );
    assert!(log(&mut c).is_empty(), "nothing reaches the bus");
}

#[test]
fn counters_load_through_preset() {
    let mut c = card();
    c.counter_configure(1, 0x13).unwrap();
    c.counter_load(1, -2).unwrap();
    assert_eq!(
        log(&mut c),
        [
            "W COUNTER.CH[1].CTRL 0x13",
            "W COUNTER.PRESET 0xfffffffe",
            "W COUNTER.CH[1].CMD 0x2"
        ]
    );
}

#[test]
fn the_halt_is_cleared_only_when_the_input_allows() {
    let mut c = card();
    // After reset: the input (open) asks for a stop and the latch is set.
    assert_eq!(c.clear_halt(), Err(Error::EstopInput));
    assert_eq!(
        log(&mut c),
        ["R SAFETY.STATUS"],
        "no CLEAR while the input asks"
    );
    c.bus().set("SAFETY.STATUS", 0b010);
    assert_eq!(
        c.clear_halt(),
        Err(Error::StillHalted),
        "the fake's latch stays"
    );
    assert_eq!(
        log(&mut c),
        ["R SAFETY.STATUS", "W SAFETY.CLEAR 0x3", "R SAFETY.STATUS"]
    );
    c.bus().set("SAFETY.STATUS", 0);
    assert_eq!(c.clear_halt(), Ok(()));
}

#[test]
fn watchdog_causes_and_irq() {
    let mut c = card();
    c.watchdog_arm(5000);
    c.watchdog_feed();
    c.enable_drives(0b1010).unwrap();
    assert_eq!(
        log(&mut c),
        [
            "W SAFETY.WDT_TIMEOUT 0x1388".to_string(),
            format!("W SAFETY.WDT_RELOAD 0x{WATCHDOG_KEY:x}"),
            "W SAFETY.ENABLE 0xa".to_string(),
        ]
    );
    c.bus().set("SAFETY.CAUSE", 0b10);
    c.bus().set("SAFETY.LOW_CAUSE", 0b100);
    let causes = c.causes();
    assert_eq!(
        (causes.card, causes.fifo_low, causes.done),
        (0b10, 0b100, 0)
    );
    assert_eq!(log(&mut c).len(), 8, "every cause register, once");
    c.clear_causes(&causes);
    assert_eq!(
        log(&mut c),
        ["W SAFETY.CAUSE 0x2", "W SAFETY.LOW_CAUSE 0x4"],
        "only the set ones"
    );
    let masks = Causes {
        card: 1,
        fifo_low: 0xf,
        ..Causes::default()
    };
    c.irq_configure(&masks, true);
    let l = log(&mut c);
    assert_eq!(l.len(), 9);
    assert!(
        l.contains(&"W SAFETY.LOW_MASK 0xf".to_string())
            && l.contains(&"W SAFETY.IRQ_CTRL 0x1".to_string()),
        "{l:?}"
    );
}

#[test]
fn shared_ram_blocks_stay_in_the_window() {
    let mut c = card();
    let words = regmap::mcu_map(&Config::default()).memories[0].words;
    c.ram_write(words - 2, &[0xbeef, 0x1234]).unwrap();
    let mut back = [0u16; 2];
    c.ram_read(words - 2, &mut back).unwrap();
    assert_eq!(back, [0xbeef, 0x1234]);
    assert_eq!(log(&mut c).len(), 4);
    assert_eq!(c.ram_write(words - 1, &[1, 2]), Err(Error::Argument));
    assert_eq!(c.ram_read(u32::MAX, &mut back), Err(Error::Argument));
    assert!(log(&mut c).is_empty());
}

#[test]
fn a_segment_the_engine_cannot_finish_touches_no_register() {
    let mut c = card();
    let stalls = Segment {
        steps: 5,
        rate: 0,
        accel: 0,
        jerk: 0,
    };
    // From 1/16 step per clock, slowing by 2^15 RATE LSBs each clock: the
    // rate reaches 0 after 8192 clocks and 256 steps, short of 1000.
    let reverses = Segment {
        steps: 1000,
        rate: 1 << 28,
        accel: i32::MIN,
        jerk: 0,
    };
    let fine = Segment {
        steps: 100,
        rate: 1 << 28,
        accel: 0,
        jerk: 0,
    };
    for bad in [stalls, reverses] {
        assert!(!motionhdl_driver::runnable(&bad), "{bad:?}");
        assert_eq!(c.push_segment(0, &bad), Err(Error::Argument));
        let mut s = Stream::new(0);
        assert_eq!(s.refill(&mut c, &[fine, bad]), Err(Error::Argument));
        assert_eq!(s.next, 0);
        assert_eq!(log(&mut c), ["R PULSE.AX[0].STATUS"], "nothing pushed");
    }
    let zero = Segment { steps: 0, ..stalls };
    let ramp = Segment {
        steps: 100,
        rate: 0,
        accel: 0,
        jerk: 1,
    };
    for ok in [fine, zero, ramp] {
        assert!(motionhdl_driver::runnable(&ok), "{ok:?}");
    }
}
