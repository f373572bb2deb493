//! The machine inputs' contract (docs/safety_io.md, "Machine inputs",
//! "Polarity, enable and causes", "Direction stops"), through the public
//! API: the prescaler, the filter's timing, polarity and enable, the causes
//! and their clears, the stops and the IRQ.

use super::*;
use crate::regmap;

const AXES: u32 = 3;

struct Bench {
    m: MachineStops,
    map: Block,
    pins: MachinePins,
}

impl Bench {
    fn new(tick_clocks: u32) -> Self {
        Self {
            m: MachineStops::new(AXES, tick_clocks),
            map: regmap::safety_io(AXES),
            pins: MachinePins::default(),
        }
    }

    fn edge(&mut self, bus: BusCycle) {
        self.m.clock(&self.map, &bus, &self.pins);
    }

    fn idle(&mut self) {
        self.edge(BusCycle::default());
    }

    fn write(&mut self, name: &str, data: u32) {
        self.edge(BusCycle::write(self.map.register(name).offset, data));
    }

    /// Idle edges until a home event shows, within 999 (the filter
    /// needs at most 4 prescaler periods).
    fn idle_until_home_event(&mut self) {
        for _ in 0..1000 {
            if self.m.home_event() != 0 {
                return;
            }
            self.idle();
        }
        panic!("the awaited home event never came");
    }

    fn reg(&self, name: &str) -> u32 {
        self.m
            .read(name)
            .unwrap_or_else(|| panic!("{name} is not a machine input register"))
    }
}

/// The pin of `kind` (MACHINE_INPUTS order) on `axis` set to `high`.
fn set_pin(pins: &mut MachinePins, kind: usize, axis: u32, high: bool) {
    let pin = match kind {
        0 => &mut pins.limit_pos,
        1 => &mut pins.limit_neg,
        2 => &mut pins.home,
        _ => &mut pins.alarm,
    };
    *pin = (*pin & !(1 << axis)) | u32::from(high) << axis;
}

/// Where input `kind` of `axis` shows: (register, bit) of its INPUTS and
/// CAUSE registers.
fn bit_of(kind: usize, axis: u32) -> (&'static str, &'static str, u32) {
    let (inputs, cause) = if kind < 2 {
        ("LIMIT_INPUTS", "LIMIT_CAUSE")
    } else {
        ("HOME_ALARM_INPUTS", "HOME_ALARM_CAUSE")
    };
    (inputs, cause, axis + if kind % 2 == 1 { 16 } else { 0 })
}

#[test]
fn the_prescaler_ticks_at_the_first_edge_and_then_every_p_clocks() {
    let mut cases = 0;
    for p in 1..=5 {
        let mut b = Bench::new(p);
        assert_eq!(b.m.tick_clocks(), p);
        for edge in 0..4 * p + 3 {
            assert_eq!(b.m.tick(), edge % p == 0, "P = {p}, edge {edge}");
            b.idle();
        }
        cases += 1;
    }
    assert_eq!(cases, 5);
}

/// The synchroniser's two edges, then FILTER_TICKS ticks reading the new
/// level: a pin first sampled high at edge j passes at the fourth tick at
/// or after edge j + 2, and by edge j + 4P + 1 at the latest.
#[test]
fn a_level_passes_at_the_fourth_tick_that_reads_it_synchronised() {
    assert_eq!(FILTER_TICKS, 4);
    let mut cases = 0;
    for p in 1..=4 {
        for j in 0..p + 2 {
            for (kind, axis) in [(0, 0), (1, 2), (2, 1), (3, 2)] {
                let what = format!(
                    "P = {p}, pin from edge {j}, {} axis {axis}",
                    MACHINE_INPUTS[kind]
                );
                let (inputs, _, bit) = bit_of(kind, axis);
                let first_tick = (j + 2_u32).div_ceil(p) * p;
                let passes = first_tick + (FILTER_TICKS - 1) * p;
                assert!(passes <= j + 4 * p + 1, "{what}: the documented bound");
                let mut b = Bench::new(p);
                for edge in 0..=passes {
                    set_pin(&mut b.pins, kind, axis, edge >= j);
                    b.idle();
                    let expected = if edge >= passes { 1 << bit } else { 0 };
                    assert_eq!(b.reg(inputs), expected, "{what}: after edge {edge}");
                }
                let other = if inputs == "LIMIT_INPUTS" {
                    "HOME_ALARM_INPUTS"
                } else {
                    "LIMIT_INPUTS"
                };
                assert_eq!(b.reg(other), 0, "{what}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 4 * (3 + 4 + 5 + 6));
}

/// A pulse shorter than 3P + 1 clocks never passes; a level held 4P + 2
/// clocks always does, rises and falls alike, whatever the tick's phase.
#[test]
fn short_pulses_never_pass_and_long_levels_always_do() {
    let mut cases = 0;
    for p in 1..=4 {
        for j in 0..p {
            for (from, len, passes) in [
                (false, 3 * p, false),
                (false, 4 * p + 2, true),
                (true, 3 * p, false),
                (true, 4 * p + 2, true),
            ] {
                let what = format!("P = {p}, from {from}, {len} clocks from edge {j}");
                let mut b = Bench::new(p);
                // Settle the level `from` first, on a tick boundary.
                b.pins.limit_pos = u32::from(from);
                for _ in 0..6 * p {
                    b.idle();
                }
                assert_eq!(b.reg("LIMIT_INPUTS"), u32::from(from), "{what}: settled");
                for _ in 0..j {
                    b.idle();
                }
                let mut seen = false;
                for edge in 0..len + 8 * p {
                    b.pins.limit_pos = u32::from(from != (edge < len));
                    b.idle();
                    seen |= b.reg("LIMIT_INPUTS") != u32::from(from);
                    if passes && edge == len - 1 {
                        assert!(seen, "{what}: passed by the level's last edge");
                    }
                }
                assert_eq!(seen, passes, "{what}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 4 * (1 + 2 + 3 + 4));
}

/// Between ticks the pin is not looked at; at a tick, reading the filtered
/// level again starts the count over.
#[test]
fn only_the_ticks_sample_the_pin_and_a_tick_reading_the_old_level_restarts_the_count() {
    let p = 3;
    // Ticks at edges 0, 3, 6, ...: the tick at edge t reads the pin of
    // edge t - 2, so edges 1, 4, 7, ...
    let passes_at = |high_at: &dyn Fn(u32) -> bool| {
        let mut b = Bench::new(p);
        for edge in 0..40 {
            b.pins.limit_pos = u32::from(high_at(edge));
            b.idle();
            if b.reg("LIMIT_INPUTS") == 1 {
                return Some(edge);
            }
        }
        None
    };
    assert_eq!(
        passes_at(&|e| e % p == 1),
        Some(12),
        "high where the ticks read: ticks 3, 6, 9, 12"
    );
    assert_eq!(
        passes_at(&|e| e % p != 1),
        None,
        "high only where no tick reads"
    );
    // Low at edge 10 only, which the tick at 12 reads: the count restarts,
    // and the level passes at the fourth tick after, 15, 18, 21, 24.
    assert_eq!(passes_at(&|e| e != 10), Some(24));
}

/// Active = filtered level XOR ACTIVE_LOW, shown enabled or not; a cause
/// and a stop only when enabled: LIMIT_POS stops up, LIMIT_NEG down, ALARM
/// both ways, HOME neither (HOME_STOP 0).
#[test]
fn polarity_and_enable_of_every_input_kind_and_axis() {
    let mut cases = 0;
    for kind in 0..4 {
        for axis in 0..AXES {
            for (pin, active_low, enabled) in (0..8).map(|c| (c & 1 == 1, c & 2 == 2, c & 4 == 4)) {
                let what = format!(
                    "{} axis {axis}, pin {pin}, ACTIVE_LOW {active_low}, ENABLE {enabled}",
                    MACHINE_INPUTS[kind]
                );
                let mut b = Bench::new(1);
                // As the docs advise: the polarity first, the enable once
                // the filter has passed the pin's level.
                let polarity = u32::from(active_low) << (axis + 16);
                let ctrl = u32::from(enabled) << axis | polarity;
                b.write(CTRL[kind], polarity);
                set_pin(&mut b.pins, kind, axis, pin);
                for _ in 0..8 {
                    b.idle();
                }
                b.write(CTRL[kind], ctrl);
                assert_eq!(b.reg(CTRL[kind]), ctrl, "{what}");
                b.idle();
                let active = pin != active_low;
                let acting = active && enabled;
                let (inputs, cause, bit) = bit_of(kind, axis);
                assert_eq!(b.reg(inputs), u32::from(active) << bit, "{what}: {inputs}");
                assert_eq!(b.reg(cause), u32::from(acting) << bit, "{what}: {cause}");
                let stops_up = acting && kind != 1 && kind != 2;
                let stops_down = acting && kind != 0 && kind != 2;
                let stops = (u32::from(stops_up) << axis, u32::from(stops_down) << axis);
                assert_eq!((b.m.stop_up(), b.m.stop_down()), stops, "{what}: stops");
                assert!(!b.m.irq_active(), "{what}: masked");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 4 * 3 * 8);
}

/// An enabled limit or alarm turning active at edge e sets its cause at
/// e + 1 (LIMIT_LATENCY 2: no step from e + 2), for as long as it acts: a
/// clear sticks only at an edge after the input stopped acting.
#[test]
fn limit_and_alarm_causes_are_levels_set_one_edge_after_acting() {
    assert_eq!(LIMIT_LATENCY, 2);
    let mut cases = 0;
    for kind in [0, 1, 3] {
        let what = MACHINE_INPUTS[kind];
        let (inputs, cause, bit) = bit_of(kind, 1);
        let mut b = Bench::new(1);
        b.write(CTRL[kind], 0b010);
        set_pin(&mut b.pins, kind, 1, true);
        let mut edges = 0;
        while b.reg(inputs) == 0 {
            edges += 1;
            assert!(edges < 1000, "the awaited input change never came");
            assert_eq!(b.reg(cause), 0, "{what}: before it acts");
            b.idle();
        }
        assert_eq!(b.reg(cause), 0, "{what}: at the edge it turns active");
        b.idle();
        assert_eq!(b.reg(cause), 1 << bit, "{what}: one edge later");
        b.write(cause, !0);
        assert_eq!(b.reg(cause), 1 << bit, "{what}: a clear while it acts");
        set_pin(&mut b.pins, kind, 1, false);
        let mut edges = 0;
        while b.reg(inputs) != 0 {
            edges += 1;
            assert!(edges < 1000, "the awaited input change never came");
            b.write(cause, 1 << bit);
            assert_eq!(b.reg(cause), 1 << bit, "{what}: still acting");
        }
        // Acting in the clock before the edge where it turned inactive.
        assert_eq!(b.reg(cause), 1 << bit, "{what}: set at the inactive edge");
        b.idle();
        assert_eq!(b.reg(cause), 1 << bit, "{what}: no clear, it stays");
        b.write(cause, 1 << bit);
        assert_eq!(b.reg(cause), 0, "{what}: the clear sticks");
        cases += 1;
    }
    assert_eq!(cases, 3);
}

#[test]
fn disabling_a_limit_stops_its_cause_from_the_next_edge() {
    let mut b = Bench::new(1);
    b.write("LIMIT_POS_CTRL", 0b001);
    b.pins.limit_pos = 0b001;
    for _ in 0..8 {
        b.idle();
    }
    b.write("LIMIT_POS_CTRL", 0); // it acted in the clock before
    assert_eq!(b.reg("LIMIT_CAUSE"), 0b001);
    b.write("LIMIT_CAUSE", 0b001);
    assert_eq!(b.reg("LIMIT_CAUSE"), 0, "disabled: the clear sticks");
    assert_eq!(b.m.stop_up(), 0);
}

/// HOME is an edge: home_event in the clock before its cause sets, once
/// per activation, and a clear sticks while it stays active.
#[test]
fn home_sets_its_cause_once_per_activation() {
    let mut b = Bench::new(1);
    b.write("HOME_CTRL", 0b101);
    b.pins.home = 0b100;
    let mut edges = 0;
    while b.reg("HOME_ALARM_INPUTS") == 0 {
        edges += 1;
        assert!(edges < 1000, "the awaited input change never came");
        assert_eq!(b.m.home_event(), 0, "before it acts");
        b.idle();
    }
    assert_eq!(b.m.home_event(), 0b100, "the clock after it turns active");
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0);
    b.idle();
    assert_eq!((b.m.home_event(), b.reg("HOME_ALARM_CAUSE")), (0, 0b100));
    b.write("HOME_ALARM_CAUSE", 0b100);
    for edge in 0..5 {
        b.idle();
        assert_eq!(
            (b.m.home_event(), b.reg("HOME_ALARM_CAUSE")),
            (0, 0),
            "edge {edge}"
        );
    }
    // Axis 0 turns active too; then axis 2 again after a release.
    b.pins.home = 0b101;
    b.idle_until_home_event();
    assert_eq!(b.m.home_event(), 0b001);
    b.idle();
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0b001);
    b.pins.home = 0b001;
    for _ in 0..8 {
        b.idle();
    }
    b.pins.home = 0b101;
    b.idle_until_home_event();
    assert_eq!(b.m.home_event(), 0b100, "a new activation of axis 2");
    b.idle();
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0b101);
    b.write("HOME_ALARM_CAUSE", 0b001);
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0b100, "only the bit written 1");
    // Not enabled: no event, no cause.
    b.write("HOME_CTRL", 0);
    b.write("HOME_ALARM_CAUSE", !0);
    b.pins.home = 0;
    for _ in 0..8 {
        b.idle();
    }
    b.pins.home = 0b111;
    for edge in 0..10 {
        b.idle();
        assert_eq!(
            (b.m.home_event(), b.reg("HOME_ALARM_CAUSE")),
            (0, 0),
            "disabled, edge {edge}"
        );
    }
}

#[test]
fn home_stop_stops_only_its_own_axis_both_ways() {
    let mut b = Bench::new(1);
    b.write("HOME_CTRL", 0b111);
    b.write("HOME_STOP", 0b010);
    b.pins.home = 0b011;
    for _ in 0..8 {
        b.idle();
    }
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0b011);
    assert_eq!((b.m.stop_up(), b.m.stop_down()), (0b010, 0b010));
    b.write("HOME_STOP", 0b100);
    assert_eq!(
        (b.m.stop_up(), b.m.stop_down()),
        (0, 0),
        "no HOME cause on axis 2"
    );
    b.write("HOME_STOP", 0b001);
    assert_eq!((b.m.stop_up(), b.m.stop_down()), (0b001, 0b001));
}

/// OR(cause AND mask) over LIMIT_CAUSE and HOME_ALARM_CAUSE.
#[test]
fn the_irq_is_cause_and_mask_of_each_cause_register() {
    let mut cases = 0;
    for (kind, mask) in [
        (0, "LIMIT_MASK"),
        (1, "LIMIT_MASK"),
        (2, "HOME_ALARM_MASK"),
        (3, "HOME_ALARM_MASK"),
    ] {
        let what = MACHINE_INPUTS[kind];
        let (_, _, bit) = bit_of(kind, 2);
        let mut b = Bench::new(1);
        b.write(CTRL[kind], 0b100);
        set_pin(&mut b.pins, kind, 2, true);
        for _ in 0..8 {
            b.idle();
        }
        assert!(!b.m.irq_active(), "{what}: masked");
        b.write(mask, !(1 << bit));
        assert!(!b.m.irq_active(), "{what}: every other mask bit");
        b.write(mask, 1 << bit);
        assert!(b.m.irq_active(), "{what}: unmasked");
        assert_eq!(b.reg(mask), 1 << bit, "{what}: {mask} reads back");
        cases += 1;
    }
    assert_eq!(cases, 4);
    assert_eq!(
        Bench::new(1).m.read("GPI_LEVEL"),
        None,
        "not a machine input register"
    );
}
