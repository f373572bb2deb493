//! The general-purpose I/O's contract (docs/safety_io.md, "General-purpose
//! inputs" and "outputs"), through the public API: GPI_LEVEL, the edge
//! causes, their clear and mask, the output pins and the safe state.

use super::*;
use crate::regmap;

struct Bench {
    io: DigitalIo,
    map: Block,
    /// The filter ticks at every edge unless set.
    tick_clocks: u32,
    edges: u32,
    pins: u32,
    halting: bool,
}

impl Bench {
    fn new() -> Self {
        Self {
            io: DigitalIo::new(),
            map: regmap::safety_io(2),
            tick_clocks: 1,
            edges: 0,
            pins: 0,
            halting: false,
        }
    }

    fn edge(&mut self, bus: BusCycle) {
        let tick = self.edges.is_multiple_of(self.tick_clocks);
        self.io
            .clock(&self.map, &bus, tick, self.halting, self.pins);
        self.edges += 1;
    }

    fn idle(&mut self) {
        self.edge(BusCycle::default());
    }

    fn write(&mut self, name: &str, data: u32) {
        self.edge(BusCycle::write(self.map.register(name).offset, data));
    }

    fn reg(&self, name: &str) -> u32 {
        self.io
            .read(name)
            .unwrap_or_else(|| panic!("{name} is not a GPIO register"))
    }

    /// Idle edges until GPI_LEVEL reads `levels`, at most `limit`.
    fn settle(&mut self, levels: u32, limit: u32) {
        for _ in 0..limit {
            if self.reg("GPI_LEVEL") == levels {
                return;
            }
            self.idle();
        }
        assert_eq!(
            self.reg("GPI_LEVEL"),
            levels,
            "not settled in {limit} edges"
        );
    }
}

/// The same filter as the machine inputs: with a tick every edge, the two
/// synchroniser edges and four ticks; input i in bit i; only 16 inputs.
#[test]
fn gpi_level_reads_each_filtered_input_in_its_bit() {
    assert_eq!(GPIO_INPUTS, 16);
    let pattern = 0xa5c3;
    let mut b = Bench::new();
    b.pins = 0xffff_0000 | pattern;
    for edge in 0..5 {
        b.idle();
        assert_eq!(b.reg("GPI_LEVEL"), 0, "edge {edge}");
    }
    b.idle();
    assert_eq!(b.reg("GPI_LEVEL"), pattern);
    assert_eq!(b.io.levels(), pattern);
    b.pins = !pattern;
    b.settle(!pattern & 0xffff, 6);
    assert_eq!(b.reg("GPI_LEVEL"), !pattern & 0xffff);
}

#[test]
fn gpi_filters_sample_only_at_ticks() {
    let mut b = Bench::new();
    b.tick_clocks = 4;
    b.pins = 0x8001;
    // Ticks at edges 0, 4, 8, ...: the fourth to read the pin is edge 16.
    for edge in 0..16 {
        b.idle();
        assert_eq!(b.reg("GPI_LEVEL"), 0, "edge {edge}");
    }
    b.idle();
    assert_eq!(b.reg("GPI_LEVEL"), 0x8001);
}

/// A selected rise (RISE[i], bits 15:0) or fall (FALL[i], bits 31:16) of
/// filtered input i at edge e sets GPI_CAUSE[i] at edge e + 1, and only it.
#[test]
fn a_selected_edge_of_a_filtered_input_sets_its_cause_one_edge_later() {
    let mut cases = 0;
    for input in 0..GPIO_INPUTS {
        for (rise, fall) in [(false, false), (true, false), (false, true), (true, true)] {
            let what = format!("input {input}, RISE {rise}, FALL {fall}");
            let mut b = Bench::new();
            let ctrl = u32::from(rise) << input | u32::from(fall) << (input + 16);
            b.write("GPI_EDGE_CTRL", ctrl);
            assert_eq!(b.reg("GPI_EDGE_CTRL"), ctrl, "{what}");
            for (high, selected) in [(true, rise), (false, fall)] {
                b.pins = u32::from(high) << input;
                let levels = b.pins;
                b.settle(levels, 8); // edge e
                assert_eq!(b.reg("GPI_CAUSE"), 0, "{what}, high {high}: edge e");
                b.idle();
                let expected = u32::from(selected) << input;
                assert_eq!(b.reg("GPI_CAUSE"), expected, "{what}, high {high}: e + 1");
                b.write("GPI_CAUSE", !0);
                b.idle();
                assert_eq!(
                    b.reg("GPI_CAUSE"),
                    0,
                    "{what}, high {high}: one cause per edge"
                );
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 16 * 4);
}

/// The selection that counts is GPI_EDGE_CTRL in the clock before e + 1.
#[test]
fn the_edge_selection_counts_in_the_clock_before_the_cause() {
    for (select_at_e, expected) in [(true, 1), (false, 0)] {
        let mut b = Bench::new();
        b.pins = 1;
        for _ in 0..5 {
            b.idle();
        }
        assert_eq!(b.reg("GPI_LEVEL"), 0, "one edge before e");
        if select_at_e {
            b.write("GPI_EDGE_CTRL", 1); // edge e
            b.idle();
        } else {
            b.idle();
            b.write("GPI_EDGE_CTRL", 1); // edge e + 1
        }
        assert_eq!(b.reg("GPI_CAUSE"), expected, "selected at e: {select_at_e}");
    }
}

#[test]
fn a_one_written_clears_its_cause_bit_and_an_edge_in_that_clock_wins() {
    let mut b = Bench::new();
    b.write("GPI_EDGE_CTRL", 0xffff);
    b.pins = 0b0110;
    b.settle(0b0110, 8);
    b.idle();
    assert_eq!(b.reg("GPI_CAUSE"), 0b0110);
    b.write("GPI_CAUSE", 0b0010);
    assert_eq!(b.reg("GPI_CAUSE"), 0b0100, "only the bit written 1");
    b.pins = 0b1110;
    b.settle(0b1110, 8);
    b.write("GPI_CAUSE", 0b1100);
    assert_eq!(
        b.reg("GPI_CAUSE"),
        0b1000,
        "input 3 rose in the clearing clock"
    );
    // A set bit stays set through a further selected edge: only a 1
    // written clears it.
    b.write("GPI_EDGE_CTRL", 0xffff_ffff);
    b.pins = 0b0110;
    b.settle(0b0110, 8);
    for _ in 0..3 {
        b.idle();
        assert_eq!(
            b.reg("GPI_CAUSE"),
            0b1000,
            "input 3 fell with its cause set"
        );
    }
}

#[test]
fn the_gpi_irq_is_cause_and_mask() {
    let mut b = Bench::new();
    b.write("GPI_EDGE_CTRL", 0x0020);
    b.pins = 0x0020;
    b.settle(0x0020, 8);
    b.idle();
    assert!(!b.io.irq_active(), "masked");
    b.write("GPI_MASK", !0x0020);
    assert_eq!(b.reg("GPI_MASK"), 0xffdf);
    assert!(!b.io.irq_active(), "every other bit");
    b.write("GPI_MASK", 0x0020);
    assert!(b.io.irq_active());
    b.write("GPI_CAUSE", 0x0020);
    assert!(!b.io.irq_active(), "cleared");
}

/// Push-pull drives the value with the pin enabled; open-drain drives a 0
/// and releases a 1. Sixteen outputs, nothing above.
#[test]
fn the_output_pins_follow_value_and_open_drain() {
    assert_eq!(GPIO_OUTPUTS, 16);
    let mut b = Bench::new();
    // Every (value, open-drain) pair: bits 0, 1, 2, 3 of each nibble.
    b.write("GPO_VALUE", 0xaaaa);
    b.write("GPO_OPEN_DRAIN", 0xcccc);
    let (value, open_drain) = (b.reg("GPO_VALUE"), b.reg("GPO_OPEN_DRAIN"));
    let mut cases = 0;
    for i in 0..16 {
        let (v, od) = (value >> i & 1 == 1, open_drain >> i & 1 == 1);
        let (out, oe) = match (v, od) {
            (v, false) => (v, true),
            (false, true) => (false, true),
            (true, true) => (false, false),
        };
        let pins = b.io.pins();
        let what = format!("output {i}, value {v}, open-drain {od}");
        assert_eq!(
            (pins.out >> i & 1 == 1, pins.oe >> i & 1 == 1),
            (out, oe),
            "{what}"
        );
        cases += 1;
    }
    assert_eq!(cases, 16);
    assert_eq!(b.io.pins().out >> 16, 0);
    assert_eq!(b.io.pins().oe >> 16, 0, "no output past 15");
    let fresh = Bench::new();
    assert_eq!(
        fresh.io.pins(),
        GpoPins { out: 0, oe: 0xffff },
        "reset: push-pull low"
    );
}

/// At every halting edge GPO_VALUE takes GPO_SAFE as it stood before the
/// edge and a GPO_VALUE write is lost; after, it stays until written.
#[test]
fn halting_edges_load_the_safe_state_from_before_the_edge() {
    let mut b = Bench::new();
    b.write("GPO_SAFE", 0x00f0);
    b.write("GPO_VALUE", 0x0f0f);
    b.halting = true;
    b.write("GPO_SAFE", 0x1234);
    assert_eq!(b.reg("GPO_VALUE"), 0x00f0, "GPO_SAFE as it stood before");
    assert_eq!(b.reg("GPO_SAFE"), 0x1234);
    b.write("GPO_VALUE", 0xffff);
    assert_eq!(b.reg("GPO_VALUE"), 0x1234, "the write is lost");
    b.halting = false;
    b.write("GPO_SAFE", 0x4321);
    b.idle();
    assert_eq!(b.reg("GPO_VALUE"), 0x1234, "kept after the halt");
    b.write("GPO_VALUE", 0x0001);
    assert_eq!(b.reg("GPO_VALUE"), 0x0001);
    assert_eq!(b.io.read("LIMIT_CAUSE"), None, "not a GPIO register");
}
