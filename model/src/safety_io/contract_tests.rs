//! The safety block's contract (docs/safety_io.md), driven through its
//! public API only: the register table, the e-stop, the watchdog, HALT and
//! ENABLE, the causes and the IRQ pin, the bus read and reset.

use super::*;

mod causes;

const AXES: u32 = 3;

/// The block with its pins held in `inputs`.
struct Bench {
    io: SafetyIo,
    map: Block,
    inputs: SafetyInputs,
}

impl Bench {
    /// As after reset, e-stop input released.
    fn new() -> Self {
        Self {
            io: SafetyIo::new(AXES, 1),
            map: regmap::safety_io(AXES),
            inputs: SafetyInputs {
                estop_ok: true,
                ..Default::default()
            },
        }
    }

    /// Released for two edges, then CLEAR.ESTOP: not halted.
    fn released() -> Self {
        let mut b = Self::new();
        b.idle();
        b.idle();
        b.write("CLEAR", 1);
        assert!(!b.io.halted(), "the bench could not clear the e-stop");
        b
    }

    fn edge(&mut self, bus: BusCycle) {
        self.io.clock(false, &bus, &self.inputs);
    }

    fn idle(&mut self) {
        self.edge(BusCycle::default());
    }

    fn write(&mut self, name: &str, data: u32) {
        self.edge(BusCycle::write(self.map.register(name).offset, data));
    }

    fn reg(&self, name: &str) -> u32 {
        self.io.read_value(self.map.register(name).offset)
    }

    fn status(&self, field: &str) -> bool {
        self.reg("STATUS") & 1 << self.map.register("STATUS").field(field).lsb != 0
    }

    /// Every address of the 7-bit bus, as a read returns it now.
    fn dump(&self) -> Vec<u32> {
        (0..128).map(|a| self.io.read_value(a)).collect()
    }
}

#[test]
fn every_register_resets_as_documented() {
    let b = Bench::new();
    let expected: Vec<u32> = (0..128)
        .map(|a| match a {
            0 => AXES, // INFO.AXES
            1 => 0x3,  // STATUS: ESTOP_INPUT and ESTOP
            _ => 0,
        })
        .collect();
    assert_eq!(b.dump(), expected);
    assert_eq!(b.map.register("INFO").offset, 0);
    assert_eq!(b.map.register("STATUS").offset, 1);
    assert!(b.io.halted(), "reset sets the e-stop latch");
    assert_eq!(b.io.drive_enable(), 0);
    assert!(b.io.irq_pin(), "the active-low pin is released");
}

/// Read-write registers keep exactly their documented fields (N = 3),
/// write-only ones read 0, read-only and unmapped addresses ignore writes.
#[test]
fn registers_read_back_their_documented_fields_and_access() {
    let per_axis = 0b111;
    let both_halves = per_axis | per_axis << 16;
    let read_write = [
        ("ENABLE", per_axis),
        ("WDT_TIMEOUT", !0),
        ("IRQ_CTRL", 1),
        ("CAUSE_MASK", 0xf),
        ("DONE_MASK", per_axis),
        ("LOW_MASK", per_axis),
        ("LIMIT_POS_CTRL", both_halves),
        ("LIMIT_NEG_CTRL", both_halves),
        ("HOME_CTRL", both_halves),
        ("ALARM_CTRL", both_halves),
        ("LIMIT_MASK", both_halves),
        ("HOME_ALARM_MASK", both_halves),
        ("GPI_EDGE_CTRL", !0),
        ("GPI_MASK", 0xffff),
        ("GPO_VALUE", 0xffff),
        ("GPO_SAFE", 0xffff),
        ("GPO_OPEN_DRAIN", 0xffff),
        ("HOME_STOP", per_axis),
        ("SOFT_LIMIT_CTRL", both_halves),
        ("SOFT_LIMIT_MASK", both_halves),
        ("COUNTER_MASK", both_halves),
    ];
    let mut b = Bench::released();
    for (name, fields) in read_write {
        b.write(name, !0);
        assert_eq!(b.reg(name), fields, "{name} after writing all ones");
        b.write(name, 0x5a5a_5a5a);
        assert_eq!(b.reg(name), 0x5a5a_5a5a & fields, "{name} after 0x5a5a5a5a");
        b.write(name, 0);
        assert_eq!(b.reg(name), 0, "{name} after writing 0");
    }
    assert_eq!(read_write.len(), 21);
    for name in ["CLEAR", "WDT_RELOAD"] {
        b.write(name, !0);
        assert_eq!(b.reg(name), 0, "write-only {name}");
    }
    // The causes set by the CTRL writes above do not matter here: clear all.
    for name in ["LIMIT_CAUSE", "HOME_ALARM_CAUSE", "CAUSE"] {
        b.write(name, !0);
    }
    let before = b.dump();
    let mut ignored = 0;
    for name in [
        "INFO",
        "STATUS",
        "WDT_COUNT",
        "LIMIT_INPUTS",
        "HOME_ALARM_INPUTS",
        "GPI_LEVEL",
    ] {
        b.write(name, !0);
        assert_eq!(b.dump(), before, "a write of read-only {name}");
        ignored += 1;
    }
    for addr in 37..128 {
        b.edge(BusCycle::write(addr, !0));
        assert_eq!(b.dump(), before, "a write of unmapped address {addr}");
        ignored += 1;
    }
    assert_eq!(ignored, 6 + 91);
}

#[test]
fn status_shows_each_flag_in_its_documented_bit() {
    let mut b = Bench::new();
    assert_eq!(b.reg("STATUS"), 0b00011, "ESTOP_INPUT and ESTOP from reset");
    b.idle();
    b.idle();
    assert_eq!(b.reg("STATUS"), 0b00010, "input released, latch held");
    b.write("CLEAR", 1);
    assert_eq!(b.reg("STATUS"), 0);
    b.write("WDT_TIMEOUT", 1);
    assert_eq!(b.reg("STATUS"), 0b01000, "ARMED");
    b.idle();
    b.idle();
    assert_eq!(b.reg("STATUS"), 0b00100, "BITTEN, ARMED cleared");
    b.write("CAUSE_MASK", 0b10);
    assert_eq!(b.reg("STATUS"), 0b10100, "IRQ with no delay");
}

#[test]
fn an_estop_input_low_at_one_edge_halts_estop_latency_edges_later() {
    assert_eq!(ESTOP_LATENCY, 3);
    let mut b = Bench::released();
    b.write("ENABLE", 0b101);
    b.write("CAUSE_MASK", 0b1);
    b.inputs.estop_ok = false;
    b.idle(); // edge k samples the input low
    b.inputs.estop_ok = true;
    assert!(!b.status("ESTOP_INPUT") && !b.io.halted(), "edge k");
    b.idle();
    assert!(b.status("ESTOP_INPUT"), "ESTOP_INPUT from edge k + 1");
    assert!(!b.io.halted() && b.reg("CAUSE") == 0 && b.io.drive_enable() == 0b101);
    b.idle();
    assert!(
        b.io.halted() && b.status("ESTOP"),
        "the latch at edge k + 2"
    );
    assert_eq!(b.reg("CAUSE"), 0b1, "CAUSE.ESTOP at edge k + 2");
    assert_eq!((b.io.drive_enable(), b.reg("ENABLE")), (0, 0));
    assert!(b.io.irq_pin(), "the pin follows one edge later");
    b.idle();
    assert!(!b.io.irq_pin());
    assert!(b.io.halted(), "the latch holds after the input is released");
    assert!(!b.status("ESTOP_INPUT"));
}

#[test]
fn the_estop_cause_sets_only_where_the_latch_rises() {
    let mut b = Bench::new();
    b.inputs.estop_ok = false;
    for edge in 0..6 {
        b.idle();
        assert_eq!(b.reg("CAUSE"), 0, "latch set from reset, edge {edge}");
    }
    b.inputs.estop_ok = true;
    b.idle();
    b.idle();
    b.write("CLEAR", 1);
    b.inputs.estop_ok = false;
    b.idle();
    b.idle();
    // The rise and a clear of the cause in the same clock: the event wins.
    b.write("CAUSE", 0b1);
    assert_eq!(b.reg("CAUSE"), 0b1);
    b.write("CAUSE", 0b1);
    for edge in 0..4 {
        b.idle();
        assert_eq!(b.reg("CAUSE"), 0, "latch still set, edge {edge}");
    }
}

/// CLEAR.ESTOP at edge k releases the latch only if the input was high at
/// edge k - 2 (STATUS.ESTOP_INPUT 0 in that clock).
#[test]
fn clear_estop_releases_only_while_the_synchronised_input_reads_released() {
    let mut cases = 0;
    for delay in 0..5 {
        let mut b = Bench::new();
        b.inputs.estop_ok = false;
        b.idle();
        b.idle();
        b.inputs.estop_ok = true; // high from edge m on
        for _ in 0..delay {
            b.idle();
        }
        let input_reads_stop = b.status("ESTOP_INPUT");
        b.write("CLEAR", 1); // edge m + delay
        assert_eq!(
            b.io.halted(),
            delay < 2,
            "clear {delay} edges after the release"
        );
        assert_eq!(input_reads_stop, delay < 2, "ESTOP_INPUT, delay {delay}");
        cases += 1;
    }
    assert_eq!(cases, 5);
    // Only the ESTOP bit of CLEAR, and only CLEAR, releases the latch.
    let mut b = Bench::new();
    b.idle();
    b.idle();
    for (name, data) in [("CLEAR", 0b10), ("ENABLE", 1), ("CAUSE", 1), ("STATUS", 1)] {
        b.write(name, data);
        assert!(b.io.halted(), "a write of {data:#x} to {name}");
    }
    b.write("CLEAR", 0xffff_fffd);
    assert!(!b.io.halted(), "CLEAR.ESTOP with other bits set");
}

#[test]
fn the_watchdog_bites_timeout_plus_one_edges_after_the_arm() {
    let mut cases = 0;
    for timeout in [1, 2, 5] {
        let mut b = Bench::released();
        b.write("ENABLE", 0b11);
        b.write("WDT_TIMEOUT", timeout); // edge e
        assert_eq!(b.reg("WDT_COUNT"), timeout, "loaded, T = {timeout}");
        assert!(b.status("ARMED"));
        for left in (0..timeout).rev() {
            b.idle();
            assert_eq!(b.reg("WDT_COUNT"), left, "counting down, T = {timeout}");
            assert!(
                !b.io.halted() && b.reg("CAUSE") == 0,
                "T = {timeout}, {left} left"
            );
        }
        b.idle(); // edge e + T + 1
        assert!(b.io.halted() && b.status("BITTEN"), "bitten, T = {timeout}");
        assert!(!b.status("ARMED") && !b.status("ESTOP"), "T = {timeout}");
        assert_eq!(b.reg("CAUSE"), 0b10, "CAUSE.WATCHDOG, T = {timeout}");
        assert_eq!(b.io.drive_enable(), 0, "T = {timeout}");
        // Off until WDT_TIMEOUT is written again: no second bite, no count.
        b.write("CAUSE", 0b10);
        b.write("CLEAR", 0b10);
        assert!(!b.io.halted(), "CLEAR.BITTEN, T = {timeout}");
        for _ in 0..timeout + 4 {
            b.idle();
            assert!(!b.io.halted() && b.reg("CAUSE") == 0 && b.reg("WDT_COUNT") == 0);
        }
        cases += 1;
    }
    assert_eq!(cases, 3);
}

#[test]
fn a_timeout_of_zero_disarms_and_an_unarmed_reload_does_nothing() {
    let mut b = Bench::released();
    b.write("WDT_TIMEOUT", 3);
    b.idle();
    b.write("WDT_TIMEOUT", 0);
    assert!(!b.status("ARMED") && b.reg("WDT_COUNT") == 0);
    for edge in 0..8 {
        b.idle();
        assert!(!b.io.halted(), "disarmed, edge {edge}");
    }
    // Unarmed after a bite, WDT_TIMEOUT still 1: the key reloads nothing.
    b.write("WDT_TIMEOUT", 1);
    b.idle();
    b.idle();
    b.write("CLEAR", 0b10);
    for edge in 0..4 {
        b.write("WDT_RELOAD", WATCHDOG_KEY);
        assert!(!b.io.halted(), "disarmed, edge {edge}");
        assert_eq!(
            (b.reg("WDT_COUNT"), b.status("ARMED")),
            (0, false),
            "edge {edge}"
        );
    }
    assert_eq!(b.reg("WDT_TIMEOUT"), 1);
}

#[test]
fn only_the_key_while_armed_reloads_the_count() {
    let mut b = Bench::released();
    b.write("WDT_TIMEOUT", 10);
    b.idle();
    b.idle();
    for wrong in [WATCHDOG_KEY ^ 1, WATCHDOG_KEY ^ 1 << 31, 0] {
        let left = b.reg("WDT_COUNT");
        b.write("WDT_RELOAD", wrong);
        assert_eq!(
            b.reg("WDT_COUNT"),
            left - 1,
            "key {wrong:#x} only counts down"
        );
    }
    assert_eq!(b.reg("WDT_COUNT"), 5);
    // The key written to another register is no reload either.
    b.write("WDT_TIMEOUT", 4);
    b.idle();
    b.write("GPO_VALUE", WATCHDOG_KEY);
    assert_eq!(b.reg("WDT_COUNT"), 2);
    b.idle();
    b.idle();
    assert_eq!(b.reg("WDT_COUNT"), 0);
    // A reload at the edge where it would bite: no bite, the count reloads.
    b.write("WDT_RELOAD", WATCHDOG_KEY);
    assert!(!b.io.halted());
    assert_eq!(b.reg("WDT_COUNT"), 4);
    for _ in 0..4 {
        b.idle();
    }
    // Likewise a WDT_TIMEOUT write at that edge.
    b.write("WDT_TIMEOUT", 2);
    assert!(!b.io.halted());
    assert_eq!(b.reg("WDT_COUNT"), 2);
    b.idle();
    b.idle();
    assert!(!b.io.halted());
    b.idle();
    assert!(b.status("BITTEN"), "2 + 1 edges after the last arm");
}

#[test]
fn a_bite_wins_over_clear_bitten_in_its_clock_and_clear_estop_is_not_clear_bitten() {
    let mut b = Bench::released();
    b.write("WDT_TIMEOUT", 1);
    b.idle();
    b.write("CLEAR", 0b10); // the biting edge
    assert!(b.status("BITTEN"), "the bite wins");
    b.write("CLEAR", 0b01);
    assert!(
        b.status("BITTEN") && b.io.halted(),
        "CLEAR.ESTOP leaves BITTEN"
    );
    b.write("CLEAR", 0b10);
    assert!(!b.io.halted());
}

#[test]
fn no_drive_is_enabled_while_halted_nor_after_until_enable_is_written() {
    let mut b = Bench::released();
    b.write("ENABLE", 0b111);
    assert_eq!(b.io.drive_enable(), 0b111);
    b.write("WDT_TIMEOUT", 1);
    b.idle();
    b.idle();
    assert!(b.io.halted());
    for edge in 0..3 {
        b.write("ENABLE", 0b011);
        assert_eq!(
            (b.io.drive_enable(), b.reg("ENABLE")),
            (0, 0),
            "edge {edge}"
        );
    }
    b.write("CLEAR", 0b10);
    b.idle();
    assert_eq!(b.io.drive_enable(), 0, "off after the clear");
    b.write("ENABLE", 0b110);
    assert_eq!(b.io.drive_enable(), 0b110);
    assert_eq!(b.io.drive_enable(), b.reg("ENABLE"));
}
