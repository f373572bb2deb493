//! The bank against docs/pulse_generator.md "Bank and registers", from
//! the bus, the stops and the pins: the register file, the outputs' path
//! and latency, POSITION and HOME_POSITION, the stops, the soft-limit
//! levels, STATUS and the decelerating stop.

use super::*;
use crate::counter::sign_extend;

const AXES: u32 = 3;
const WIDTH: u32 = 12;
const STEP_EVERY_4: u32 = 1 << 30;

struct Bench {
    bank: PulseBank,
    map: Block,
    stops: Stops,
    snapshot: bool,
}

impl Bench {
    fn new() -> Self {
        let mut bank = PulseBank::new(AXES, WIDTH);
        bank.clock(true, &BusCycle::default(), false);
        Self {
            bank,
            map: regmap::pulse_bank(AXES, WIDTH),
            stops: Stops::default(),
            snapshot: false,
        }
    }

    fn ax(&self, i: u32, name: &str) -> u32 {
        self.map.array("AX").address(i, name)
    }

    fn clock(&mut self, bus: BusCycle) {
        let stops = self.stops;
        self.bank.clock_stopping(false, &bus, self.snapshot, &stops);
    }

    fn idle(&mut self, clocks: usize) {
        (0..clocks).for_each(|_| self.clock(BusCycle::default()));
    }

    fn write(&mut self, i: u32, name: &str, value: u32) {
        self.clock(BusCycle::write(self.ax(i, name), value));
    }

    fn write_run(&mut self, value: u32) {
        self.clock(BusCycle::write(self.map.register("RUN").offset, value));
    }

    fn read_addr(&mut self, addr: u32) -> u32 {
        self.clock(BusCycle::read(addr));
        self.idle(1);
        self.bank.rdata()
    }

    fn read(&mut self, i: u32, name: &str) -> u32 {
        self.read_addr(self.ax(i, name))
    }

    fn status(&self, i: u32) -> u32 {
        self.bank.read_value(self.ax(i, "STATUS"))
    }

    /// STATUS.BRAKING of axis `i`.
    fn braking(&self, i: u32) -> bool {
        self.status(i) >> 28 & 1 == 1
    }

    /// Writes all four words of a segment into axis `i`'s tail slot and
    /// pushes it.
    fn push_segment(&mut self, i: u32, steps: u32, rate: u32, accel: u32) {
        self.write(i, "SEG_STEPS", steps);
        self.write(i, "SEG_RATE", rate);
        self.write(i, "SEG_ACCEL", accel);
        self.write(i, "SEG_JERK", 0);
        self.write(i, "SEG_PUSH", 0);
    }

    /// Axis `i` at `rate` with the fastest timing, running.
    fn start(&mut self, i: u32, ctrl: u32, rate: u32) {
        self.write(i, "STEP_TIMING", 1 | 1 << 16);
        self.write(i, "DIR_TIMING", 1 | 1 << 16);
        self.write(i, "CTRL", ctrl);
        self.write(i, "RATE", rate);
        let run = self.bank.read_value(self.map.register("RUN").offset);
        self.write_run(run | 1 << i);
    }

    /// POSITION of axis `i` through a snapshot.
    fn position(&mut self, i: u32) -> i32 {
        self.snapshot = true;
        self.idle(1);
        self.snapshot = false;
        self.read(i, "POSITION") as i32
    }
}

#[test]
fn registers_keep_their_fields() {
    let mut b = Bench::new();
    let info = b.read_addr(b.map.register("INFO").offset);
    assert_eq!(info, AXES | WIDTH << 8);
    b.write_run(u32::MAX);
    assert_eq!(b.read_addr(1), 0b111, "RUN: one bit per axis");
    b.write_run(0);
    let kept = [
        ("CTRL", 0b111),
        ("RATE", u32::MAX),
        ("STEP_TIMING", u32::MAX),
        ("DIR_TIMING", u32::MAX),
        ("FIFO_LOW_WATER", 0x7f),
        ("DECEL", 0x7fff_ffff),
    ];
    for i in 0..AXES {
        for (name, mask) in kept {
            b.write(i, name, u32::MAX);
            assert_eq!(b.read(i, name), mask, "AX[{i}].{name}");
            let other = (i + 1) % AXES;
            assert_eq!(b.read(other, name), 0, "AX[{other}].{name} after AX[{i}]'s");
            b.write(i, name, 0x5a5a_5a5a);
            assert_eq!(b.read(i, name), 0x5a5a_5a5a & mask, "AX[{i}].{name}");
            b.write(i, name, 0);
        }
        // WIDTH bits stored, read sign-extended.
        for name in ["SOFT_MIN", "SOFT_MAX"] {
            for (written, read) in [(0x7ff, 0x7ff), (0x800, 0xffff_f800), (0x1234, 0x234)] {
                b.write(i, name, written);
                assert_eq!(b.read(i, name), read, "AX[{i}].{name} = {written:#x}");
            }
        }
        for name in ["SEG_STEPS", "SEG_RATE", "SEG_ACCEL", "SEG_JERK", "SEG_PUSH"] {
            b.write(i, name, u32::MAX);
            assert_eq!(b.read(i, name), 0, "AX[{i}].{name} is write-only");
        }
        assert_eq!(b.read(i, "HOME_POSITION"), 0);
        assert_eq!(b.read(i, "POSITION"), 0);
    }
    let decoded: Vec<u32> = b.map.decoded().iter().map(|d| d.0).collect();
    for addr in (0..512).filter(|a| !decoded.contains(a)) {
        assert_eq!(b.bank.read_value(addr), 0, "word {addr}");
    }
    // Only the map's 9 address bits reach the decoder.
    b.write(1, "FIFO_LOW_WATER", 0x5a);
    assert_eq!(b.read_addr(512 + b.ax(1, "FIFO_LOW_WATER")), 0x7f & 0x5a);
}

/// Per axis in one clock: (F1, F2) at the pins and the generator's (S1, S2).
type AxisPins = ((bool, bool), (bool, bool));

/// Every axis's pins for `clocks` clocks.
fn run(b: &mut Bench, clocks: usize) -> Vec<Vec<AxisPins>> {
    (0..clocks)
        .map(|_| {
            b.idle(1);
            (0..AXES as usize)
                .map(|i| (b.bank.outputs(i), b.bank.generator(i).outputs()))
                .collect()
        })
        .collect()
}

/// F1/F2 are the registered selector's outputs through one more register:
/// two edges behind S1/S2, K choosing pulse+direction or CW/CCW; the
/// steps counted at F1 (or F2) are the POSITION the snapshot reads.
#[test]
fn steps_reach_the_pins_two_edges_after_s1_in_either_mode() {
    for (mode, rate) in [
        (0, STEP_EVERY_4),
        (0, STEP_EVERY_4.wrapping_neg()),
        (1, STEP_EVERY_4),
        (1, STEP_EVERY_4.wrapping_neg()),
    ] {
        let mut b = Bench::new();
        b.start(1, mode, rate);
        let history = run(&mut b, 300);
        b.write_run(0);
        let tail = run(&mut b, 20);
        let all: Vec<_> = history.into_iter().chain(tail).collect();
        for k in 2..all.len() {
            let (s1, s2) = all[k - 2][1].1;
            let expected = crate::pulse_mode_selector::from_truth_table(mode == 1, s2, s1);
            assert_eq!(
                all[k][1].0, expected,
                "mode {mode} rate {rate:#x} clock {k}"
            );
            assert_eq!(all[k][0].0, (false, false), "axis 0 never ran");
        }
        let steps = all.windows(2).filter(|w| {
            let (now, before) = (w[1][1].0, w[0][1].0);
            let f1 = now.0 && !before.0;
            f1 || (mode == 1 && now.1 && !before.1)
        });
        let steps = steps.count() as i32;
        let sign = if rate as i32 > 0 { 1 } else { -1 };
        assert!(steps > 60, "{steps}");
        assert_eq!(b.position(1), sign * steps, "mode {mode} rate {rate:#x}");
        assert_eq!(b.position(0), 0);
    }
}

/// With CTRL.QUADRATURE the pins carry the Gray phase of the position,
/// through two registers (the phase's and the pins').
#[test]
fn quadrature_pins_follow_the_position() {
    let mut b = Bench::new();
    b.start(2, 0b010, STEP_EVERY_4.wrapping_neg());
    let mut positions = vec![b.bank.generator(2).position];
    for _ in 0..200 {
        b.idle(1);
        let k = positions.len();
        if k >= 2 {
            assert_eq!(b.bank.outputs(2), quadrature(positions[k - 2]), "clock {k}");
        }
        positions.push(b.bank.generator(2).position);
    }
    assert!(positions.last().unwrap().wrapping_neg() > 40);
}

/// POSITION changes only at a snapshot; HOME_POSITION is live: the
/// position in the clock the home input is high.
#[test]
fn position_waits_for_the_snapshot_and_home_captures_live() {
    let mut b = Bench::new();
    b.start(0, 0, STEP_EVERY_4);
    b.idle(100);
    let at_snapshot = b.position(0);
    assert!(at_snapshot > 15);
    b.idle(100);
    assert_eq!(
        b.read(0, "POSITION") as i32,
        at_snapshot,
        "no snapshot, no change"
    );
    let live = crate::counter::wrap(b.bank.generator(0).position, WIDTH);
    b.stops.home = 1;
    b.idle(1);
    b.stops.home = 0;
    b.idle(30);
    assert_eq!(b.read(0, "HOME_POSITION"), sign_extend(live, WIDTH));
    assert_eq!(b.read(1, "HOME_POSITION"), 0);
    assert!(b.position(0) > at_snapshot);
    // Axis 2's home input captures axis 2, and only it.
    b.start(2, 0, STEP_EVERY_4.wrapping_neg());
    b.idle(100);
    let live = crate::counter::wrap(b.bank.generator(2).position, WIDTH);
    assert!(sign_extend(live, WIDTH) as i32 <= -15);
    let home_0 = b.read(0, "HOME_POSITION");
    b.stops.home = 0b100;
    b.idle(1);
    b.stops.home = 0;
    assert_eq!(b.read(2, "HOME_POSITION"), sign_extend(live, WIDTH));
    assert_eq!(b.read(0, "HOME_POSITION"), home_0);
}

/// HALT stops every axis: RUN cleared (a write of it ignored while HALT
/// lasts), queued steps dropped. A direction stop stops only an axis
/// heading that way.
#[test]
fn halt_and_direction_stops() {
    let mut b = Bench::new();
    b.start(0, 0, STEP_EVERY_4);
    b.start(1, 0, STEP_EVERY_4.wrapping_neg());
    b.idle(50);
    b.stops.up = 0b11;
    b.idle(1);
    assert_eq!(b.read_addr(1), 0b10, "up stops only the axis heading up");
    b.stops.up = 0;
    b.stops.down = 0b10;
    b.idle(1);
    assert_eq!(b.read_addr(1), 0, "down stops axis 1");
    b.stops.down = 0;
    b.idle(20);
    let stopped = (b.position(0), b.position(1));
    b.idle(50);
    assert_eq!((b.position(0), b.position(1)), stopped);
    b.write_run(0b111);
    b.idle(40);
    b.stops.halt = true;
    b.write_run(0b111);
    assert_eq!(
        b.read_addr(1),
        0,
        "HALT clears RUN, and a write of it is ignored"
    );
    for i in 0..3 {
        assert_eq!(b.status(i) & 0xffff, 0, "AX[{i}]: queued steps dropped");
    }
    b.stops.halt = false;
    b.write_run(0b001);
    assert_eq!(b.read_addr(1), 0b001);
}

/// The soft-limit levels: POSITION ≥ SOFT_MAX and POSITION ≤ SOFT_MIN,
/// signed WIDTH-bit compares, one edge behind POSITION.
#[test]
fn soft_limit_levels_are_signed_compares_one_edge_late() {
    for (min, max, rate) in [
        (-3i32, 5i32, STEP_EVERY_4),
        (-3, 5, STEP_EVERY_4.wrapping_neg()),
        (-2048, 2047, STEP_EVERY_4),
    ] {
        let mut b = Bench::new();
        b.write(0, "SOFT_MIN", min as u32);
        b.write(0, "SOFT_MAX", max as u32);
        b.start(0, 0, rate);
        let (mut above, mut below) = (0, 0);
        for k in 0..200 {
            let position = sign_extend(
                crate::counter::wrap(b.bank.generator(0).position, WIDTH),
                WIDTH,
            ) as i32;
            b.idle(1);
            let levels = b.bank.soft_levels();
            let expected = (u32::from(position >= max), u32::from(position <= min));
            assert_eq!(
                (levels.0 & 1, levels.1 & 1),
                expected,
                "min {min} max {max} clock {k} at {position}"
            );
            // Axes 1 and 2 stand at 0 with both limits 0: both levels.
            assert_eq!((levels.0 >> 1, levels.1 >> 1), (0b11, 0b11), "axes 1 and 2");
            above += expected.0;
            below += expected.1;
        }
        assert!(
            above > 0 || below > 0 || max == 2047,
            "min {min} max {max}: a level never rose"
        );
    }
}

/// STATUS: FIFO_LEVEL and FIFO_LOW against FIFO_LOW_WATER, OVERFLOW from
/// a push into a full FIFO (cleared by writing CTRL), a segment's MOVING
/// and DONE, BUSY until the steps are out.
#[test]
fn status_follows_the_fifo_and_the_move() {
    let mut b = Bench::new();
    let field = |s: u32, lsb: u32, bits: u32| s >> lsb & ((1 << bits) - 1);
    assert_eq!(field(b.status(0), 27, 1), 1, "FIFO_LOW when empty");
    for _ in 0..3 {
        b.push_segment(0, 5, STEP_EVERY_4, 0);
    }
    assert_eq!(field(b.status(0), 20, 7), 3, "FIFO_LEVEL");
    b.write(0, "FIFO_LOW_WATER", 2);
    assert_eq!(field(b.status(0), 27, 1), 0);
    assert!(
        !b.bank.fifo_low(0),
        "the safety block's input is STATUS.FIFO_LOW"
    );
    b.write(0, "FIFO_LOW_WATER", 3);
    assert_eq!(field(b.status(0), 27, 1), 1);
    assert!(b.bank.fifo_low(0));
    for _ in 0..70 {
        b.write(0, "SEG_PUSH", 0);
    }
    assert_eq!(field(b.status(0), 19, 1), 1, "OVERFLOW");
    assert_eq!(field(b.status(0), 20, 7), 64);
    assert_eq!(b.bank.engine(0).level(), 64, "the engine behind STATUS");
    b.write(0, "CTRL", 0);
    assert_eq!(field(b.status(0), 19, 1), 0, "a CTRL write clears OVERFLOW");
    // A fresh axis: one 5-step segment.
    b.push_segment(1, 5, STEP_EVERY_4, 0);
    b.start(1, 0b100, 0);
    let mut seen = Vec::new();
    for _ in 0..80 {
        let s = b.status(1);
        let flags = (field(s, 16, 1), field(s, 17, 1), field(s, 18, 1));
        if seen.last() != Some(&flags) {
            seen.push(flags);
        }
        assert_eq!(b.bank.move_done(1), flags.2 == 1 && flags.0 == 0);
        b.idle(1);
    }
    // (BUSY, MOVING, DONE): running, running with steps out, done with
    // the last steps still out, then done and out.
    assert_eq!(seen.first(), Some(&(0, 0, 0)));
    assert_eq!(seen.last(), Some(&(0, 0, 1)));
    assert!(
        seen.contains(&(1, 1, 0)) && seen.contains(&(1, 0, 1)),
        "{seen:?}"
    );
    assert_eq!(b.position(1), 5);
    assert_eq!(b.bank.nco_rate(1), 0);
}

/// With DECEL set, a stop in the direction of motion brakes: BRAKING set,
/// the NCO's rate falls without turning, RUN cleared, steps go on while it
/// brakes; with DECEL 0, or on HALT whatever DECEL says, the stop is
/// instant.
#[test]
fn decel_brakes_a_direction_stop_and_halt_is_instant() {
    let (rate, decel) = (STEP_EVERY_4 >> 4, 1 << 30);
    let cases = [(false, decel), (false, 0), (true, decel)];
    for axis in [0u32, 2] {
        for down in [false, true] {
            for (halt, decel) in cases {
                let case = format!("axis {axis} down {down} halt {halt} DECEL {decel:#x}");
                brake_case(axis, down, halt, rate, decel, &case);
            }
        }
    }
}

/// One case of the test above, heading up (or down with `down`).
fn brake_case(axis: u32, down: bool, halt: bool, rate: u32, decel: u32, case: &str) {
    let sign = if down { -1 } else { 1 };
    let mut b = Bench::new();
    b.write(axis, "DECEL", decel);
    b.start(axis, 0, (sign * rate as i32) as u32);
    b.idle(200);
    assert!(!b.braking(axis), "{case}: no brake before a stop");
    assert_eq!(b.read_addr(1), 1 << axis, "{case}: running");
    let before = b.position(axis);
    match (halt, down) {
        (true, _) => b.stops.halt = true,
        (false, false) => b.stops.up = 1 << axis,
        (false, true) => b.stops.down = 1 << axis,
    }
    let mut rates = Vec::new();
    for _ in 0..6000 {
        b.idle(1);
        if b.braking(axis) {
            rates.push(sign * b.bank.nco_rate(axis as usize));
        }
    }
    assert_eq!(b.read_addr(1), 0, "{case}: RUN cleared");
    assert!(
        rates.windows(2).all(|w| w[1] <= w[0] && w[1] >= 0),
        "{case}: the rate falls toward 0 without turning"
    );
    let after = b.position(axis);
    b.idle(1000);
    assert_eq!(b.position(axis), after, "{case}: stopped");
    let travel = sign * (after - before);
    if decel != 0 && !halt {
        assert!(rates.len() > 1000, "{case}: braked {} clocks", rates.len());
        assert!(
            rates[0] <= rate as i32 && rates[0] > rate as i32 / 2,
            "{case}"
        );
        assert!(travel >= 10, "{case}: {before}..{after}");
    } else {
        assert!(rates.is_empty(), "{case}");
        assert!((0..=3).contains(&travel), "{case}: {before}..{after}");
    }
}

/// With DECEL set, a stop on an axis standing still (RUN set, rate 0)
/// starts no brake in either direction: only a rate heading into a stop
/// brakes.
#[test]
fn a_still_axis_never_brakes() {
    let mut b = Bench::new();
    b.write(1, "DECEL", 1 << 30);
    b.start(1, 0, 0);
    b.idle(10);
    b.stops.up = 0b010;
    b.stops.down = 0b010;
    for clock in 0..50 {
        b.idle(1);
        assert!(!b.braking(1), "clock {clock}: BRAKING");
    }
    assert_eq!(b.read_addr(1), 0b010, "RUN kept");
}

/// `clock` is one edge with no stop: the same as `clock_stopping` with
/// none, every pin and `rdata` every clock.
#[test]
fn clock_is_an_edge_without_stops() {
    let mut plain = Bench::new();
    let mut stopping = Bench::new();
    let map = plain.map.clone();
    let ax = |name: &str| map.array("AX").address(0, name);
    let script = [
        BusCycle::write(ax("STEP_TIMING"), 1 | 1 << 16),
        BusCycle::write(ax("DIR_TIMING"), 1 | 1 << 16),
        BusCycle::write(ax("RATE"), STEP_EVERY_4),
        BusCycle::write(map.register("RUN").offset, 1),
    ];
    let mut steps = 0;
    for k in 0..300 {
        let bus = script
            .get(k)
            .copied()
            .unwrap_or(BusCycle::read(ax("STATUS")));
        plain.bank.clock(false, &bus, k % 50 == 0);
        stopping.snapshot = k % 50 == 0;
        stopping.clock(bus);
        assert_eq!(plain.bank.outputs(0), stopping.bank.outputs(0), "clock {k}");
        assert_eq!(plain.bank.rdata(), stopping.bank.rdata(), "clock {k}");
        steps += u32::from(plain.bank.outputs(0).0);
    }
    assert!(steps > 50, "{steps}");
}

/// Reset empties the FIFO but not its RAM (docs/pulse_generator.md: "reset
/// clears the FIFO's pointers and flags, not the RAM"): a bare SEG_PUSH
/// after a reset queues the words written before it.
#[test]
fn reset_keeps_the_segment_words() {
    let mut b = Bench::new();
    b.push_segment(0, 7, STEP_EVERY_4, 0);
    let level = |b: &Bench| b.status(0) >> 20 & 0x7f;
    assert_eq!(level(&b), 1);
    b.bank.clock(true, &BusCycle::default(), false);
    assert_eq!(level(&b), 0, "reset empties the FIFO");
    b.write(0, "SEG_PUSH", 0);
    b.start(0, 0b100, 0);
    b.idle(200);
    assert_eq!(b.position(0), 7, "the slot kept SEG_STEPS and SEG_RATE");
}

/// "Heads up" and "heads down" (docs "Direction stops") take the NCO's
/// rate or PENDING, each by its sign: a stop leaves an axis standing still
/// or heading the other way, and stops one whose only steps toward it are
/// queued (rate 0, PENDING ≠ 0), dropping them.
#[test]
fn a_stop_takes_the_rate_or_the_queue_heading_into_it() {
    let mut b = Bench::new();
    b.start(0, 0, 0);
    b.start(1, 0, STEP_EVERY_4);
    b.start(2, 0, STEP_EVERY_4);
    b.idle(20);
    b.stops.up = 0b101;
    b.stops.down = 0b011;
    b.idle(3);
    assert_eq!(
        b.read_addr(1),
        0b011,
        "still, or heading up into a down stop: kept; axis 2 up into up: stopped"
    );
    for up in [true, false] {
        let mut b = Bench::new();
        let rate = if up {
            STEP_EVERY_4
        } else {
            STEP_EVERY_4.wrapping_neg()
        };
        // Axis 1 (its bits above bit 0): S1 held high for 65535 clocks, so
        // the steps commanded queue up.
        b.write(1, "STEP_TIMING", 0xffff | 1 << 16);
        b.write(1, "DIR_TIMING", 1 | 1 << 16);
        b.write(1, "RATE", rate);
        b.write_run(0b010);
        b.idle(40);
        b.write(1, "RATE", 0);
        b.idle(3);
        let pending = |b: &Bench| sign_extend(b.status(1) & 0xffff, 16) as i32;
        let queued = pending(&b);
        assert!(queued.abs() >= 5 && (queued > 0) == up, "{queued}");
        let (toward, away) = if up { (0b010, 0) } else { (0, 0b010) };
        b.stops.up = away;
        b.stops.down = toward;
        b.idle(3);
        assert_eq!(
            b.read_addr(1),
            0b010,
            "up {up}: a stop the queue heads away from"
        );
        assert_eq!(pending(&b), queued, "up {up}");
        b.stops.up = toward;
        b.stops.down = away;
        b.idle(3);
        assert_eq!(b.read_addr(1), 0, "up {up}: RUN cleared");
        assert_eq!(pending(&b), 0, "up {up}: the queue dropped");
    }
}

/// A running segment's ramp advances only in clocks where its NCO runs
/// (docs "Ramps"): with RUN cleared the rate holds, and it goes on from
/// there once RUN is set again.
#[test]
fn a_segment_ramp_holds_while_run_is_low() {
    let mut b = Bench::new();
    b.push_segment(0, 1000, 0, 1 << 20);
    b.start(0, 0b100, 0);
    b.idle(100);
    b.write_run(0);
    b.idle(2);
    let held = b.bank.nco_rate(0);
    assert!(held > 1000, "{held}");
    for clock in 0..100 {
        b.idle(1);
        assert_eq!(b.bank.nco_rate(0), held, "clock {clock}");
    }
    b.write_run(1);
    b.idle(10);
    assert!(b.bank.nco_rate(0) > held);
}
