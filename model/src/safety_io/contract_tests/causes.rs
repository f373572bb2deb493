//! The safety block's causes, IRQ pin, bus read, stops, the top's wiring
//! helpers and reset (docs/safety_io.md, "Causes and the IRQ pin").

use super::super::*;
use super::{Bench, AXES};

#[test]
fn system_causes_set_on_their_events_and_a_one_written_clears_them() {
    let mut b = Bench::released();
    b.inputs.doorbell = true;
    b.idle();
    assert_eq!(b.reg("CAUSE"), 0b0100, "DOORBELL");
    b.idle();
    b.inputs.doorbell = false;
    assert_eq!(b.reg("CAUSE"), 0b0100, "a second ring leaves it set");
    b.inputs.servo_tick = true;
    b.idle();
    b.inputs.servo_tick = false;
    assert_eq!(b.reg("CAUSE"), 0b1100, "SERVO_TICK");
    b.write("CAUSE", 0b0100);
    assert_eq!(b.reg("CAUSE"), 0b1000, "only the bit written 1 clears");
    b.inputs.servo_tick = true;
    b.write("CAUSE", 0b1000);
    assert_eq!(
        b.reg("CAUSE"),
        0b1000,
        "an event in the clearing clock wins"
    );
    b.inputs.servo_tick = false;
    b.write("CAUSE", 0b1000);
    assert_eq!(b.reg("CAUSE"), 0);
}

#[test]
fn done_and_low_causes_set_on_rises_per_axis() {
    let mut cases = 0;
    for (cause, mask) in [("DONE_CAUSE", "DONE_MASK"), ("LOW_CAUSE", "LOW_MASK")] {
        let set = |b: &mut Bench, levels: u32| {
            if cause == "DONE_CAUSE" {
                b.inputs.done = levels;
            } else {
                b.inputs.low = levels;
            }
        };
        let mut b = Bench::released();
        // A level high since reset is a rise at the first edge; bits past
        // the axes are no axes.
        let mut fresh = Bench::new();
        set(&mut fresh, !0);
        fresh.idle();
        assert_eq!(fresh.reg(cause), 0b111, "{cause} at the first edge");
        set(&mut b, 0b010);
        b.idle();
        assert_eq!(b.reg(cause), 0b010, "{cause}: axis 1 rose");
        b.write(cause, 0b010);
        b.idle();
        assert_eq!(b.reg(cause), 0, "{cause}: a level that stays is no event");
        set(&mut b, 0b011);
        b.write(cause, 0b001);
        assert_eq!(b.reg(cause), 0b001, "{cause}: a rise wins over the clear");
        assert!(!b.status("IRQ"), "{cause} masked");
        b.write(mask, 0b010);
        assert!(!b.status("IRQ"), "{mask} covers no set {cause}");
        b.write(mask, 0b001);
        assert!(b.status("IRQ"), "{cause} AND {mask}");
        set(&mut b, 0);
        b.idle();
        set(&mut b, 0b100);
        b.idle();
        assert_eq!(b.reg(cause), 0b101, "{cause}: axis 2 rose");
        cases += 1;
    }
    assert_eq!(cases, 2);
}

/// STATUS.IRQ = OR over every cause register of (cause AND mask), with no
/// delay; the pin follows it and IRQ_CTRL.ACTIVE_HIGH one edge later.
#[test]
fn each_cause_register_drives_the_irq_through_its_mask() {
    // (cause, mask, setup writes, the inputs that raise bit `bit`, bit)
    type Source = (
        &'static str,
        &'static str,
        &'static [(&'static str, u32)],
        fn(&mut SafetyInputs),
        u32,
    );
    let sources: [Source; 9] = [
        ("CAUSE", "CAUSE_MASK", &[], |i| i.doorbell = true, 2),
        ("CAUSE", "CAUSE_MASK", &[], |i| i.servo_tick = true, 3),
        ("DONE_CAUSE", "DONE_MASK", &[], |i| i.done = 0b100, 2),
        ("LOW_CAUSE", "LOW_MASK", &[], |i| i.low = 0b010, 1),
        (
            "LIMIT_CAUSE",
            "LIMIT_MASK",
            &[("LIMIT_NEG_CTRL", 0b001)],
            |i| i.machine.limit_neg = 0b001,
            16,
        ),
        (
            "HOME_ALARM_CAUSE",
            "HOME_ALARM_MASK",
            &[("ALARM_CTRL", 0b010)],
            |i| i.machine.alarm = 0b010,
            17,
        ),
        (
            "GPI_CAUSE",
            "GPI_MASK",
            &[("GPI_EDGE_CTRL", 1 << 9)],
            |i| i.machine.gpi = 1 << 9,
            9,
        ),
        (
            "SOFT_LIMIT_CAUSE",
            "SOFT_LIMIT_MASK",
            &[("SOFT_LIMIT_CTRL", 0b100 << 16)],
            |i| i.at_soft_min = 0b100,
            18,
        ),
        (
            "COUNTER_CAUSE",
            "COUNTER_MASK",
            &[],
            |i| i.counter_error = 0b001,
            0,
        ),
    ];
    let mut cases = 0;
    for (cause, mask, setup, raise, bit) in sources {
        for active_high in [false, true] {
            let what = format!("{cause} bit {bit}, ACTIVE_HIGH {active_high}");
            let mut b = Bench::released();
            b.write("IRQ_CTRL", u32::from(active_high));
            for &(name, value) in setup {
                b.write(name, value);
            }
            b.idle();
            assert_eq!(b.io.irq_pin(), !active_high, "{what}: idle pin");
            raise(&mut b.inputs);
            for _ in 0..12 {
                b.idle(); // through the filters where there are any
            }
            assert_eq!(b.reg(cause), 1 << bit, "{what}: the cause sets");
            assert!(!b.status("IRQ"), "{what}: masked");
            assert_eq!(b.io.irq_pin(), !active_high, "{what}: masked pin");
            b.write(mask, !(1 << bit));
            assert!(!b.status("IRQ"), "{what}: the other mask bits");
            b.write(mask, 1 << bit);
            assert!(b.status("IRQ"), "{what}: STATUS.IRQ at the mask's edge");
            assert_eq!(b.io.irq_pin(), !active_high, "{what}: not yet the pin");
            b.idle();
            assert_eq!(
                b.io.irq_pin(),
                active_high,
                "{what}: the pin one edge later"
            );
            // The event gone and the cause cleared: released one edge later.
            b.inputs = Bench::new().inputs;
            for _ in 0..12 {
                b.idle();
            }
            b.write(cause, 1 << bit);
            assert!(!b.status("IRQ"), "{what}: cleared");
            assert_eq!(b.io.irq_pin(), active_high, "{what}: still the pin");
            b.idle();
            assert_eq!(b.io.irq_pin(), !active_high, "{what}: released");
            cases += 1;
        }
    }
    assert_eq!(cases, 18);
}

#[test]
fn the_irq_pin_takes_a_new_polarity_one_edge_after_its_write() {
    let mut b = Bench::released();
    assert!(b.io.irq_pin());
    b.write("IRQ_CTRL", 1);
    assert!(b.io.irq_pin(), "the write's own edge");
    b.idle();
    assert!(!b.io.irq_pin(), "active high, no cause: low");
    b.write("IRQ_CTRL", 0b10);
    b.idle();
    assert!(b.io.irq_pin(), "only bit 0 is ACTIVE_HIGH");
}

#[test]
fn a_read_loads_rdata_at_the_edge_after_its_address_and_then_holds() {
    let mut b = Bench::released();
    b.write("GPO_SAFE", 0x1234);
    let info = b.map.register("INFO").offset;
    let safe = b.map.register("GPO_SAFE").offset;
    b.edge(BusCycle::read(safe));
    assert_eq!(b.io.rdata(), 0, "not at the address's edge");
    b.idle();
    assert_eq!(b.io.rdata(), 0x1234);
    for _ in 0..3 {
        b.idle();
        assert_eq!(b.io.rdata(), 0x1234, "holds");
    }
    // Back to back; only addr[6:0] reaches the decoder.
    b.edge(BusCycle::read(info));
    b.edge(BusCycle::read(0x80 | safe));
    assert_eq!(b.io.rdata(), AXES);
    b.idle();
    assert_eq!(b.io.rdata(), 0x1234, "address {:#x}", 0x80 | safe);
    // Writes decode the same seven bits.
    b.edge(BusCycle::write(0x180 | safe, 0x55));
    assert_eq!(b.reg("GPO_SAFE"), 0x55);
}

#[test]
fn stops_take_the_soft_limits_and_never_the_counter_events() {
    let mut b = Bench::released();
    b.write("SOFT_LIMIT_CTRL", 0b010 | 0b100 << 16);
    b.inputs.at_soft_max = 0b111;
    b.inputs.at_soft_min = 0b111;
    b.inputs.counter_error = 0b001;
    b.inputs.index_seen = 0b001;
    b.idle();
    let stops = b.io.stops();
    assert_eq!((stops.up, stops.down), (0b010, 0b100));
    assert_eq!((b.io.stop_up(), b.io.stop_down()), (0b010, 0b100));
    assert!(!stops.halt && stops.home == 0);
    assert_eq!(b.reg("COUNTER_CAUSE"), 0b001 | 0b001 << 16);
    let halted = Bench::new();
    assert!(halted.io.stops().halt, "HALT from reset");
}

#[test]
fn the_home_event_reaches_the_stops_in_the_clock_before_its_cause() {
    let mut b = Bench::released();
    b.write("HOME_CTRL", 0b100);
    b.inputs.machine.home = 0b100;
    let mut edges = 0;
    while b.io.home_event() == 0 {
        b.idle();
        edges += 1;
        assert!(edges < 20, "no home event");
    }
    assert_eq!(b.io.stops().home, 0b100);
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0);
    b.idle();
    assert_eq!(b.reg("HOME_ALARM_CAUSE"), 0b100);
    assert_eq!(b.io.home_event(), 0, "once per activation");
}

#[test]
fn from_pulses_reads_every_axis_done_and_low_and_the_soft_comparisons() {
    let pulses = PulseBank::new(AXES, 32);
    let pins = MachinePins {
        alarm: 0b10,
        ..Default::default()
    };
    let inputs = SafetyInputs::from_pulses(false, pins, &pulses);
    assert_eq!((inputs.estop_ok, inputs.machine), (false, pins));
    assert_eq!(
        (inputs.at_soft_max, inputs.at_soft_min),
        pulses.soft_levels()
    );
    for i in 0..AXES as usize {
        assert_eq!(
            inputs.done >> i & 1 == 1,
            pulses.move_done(i),
            "done, axis {i}"
        );
        assert_eq!(
            inputs.low >> i & 1 == 1,
            pulses.fifo_low(i),
            "low, axis {i}"
        );
    }
    // After reset no move is done yet (DONE is sticky) and every FIFO is
    // empty, at its low mark.
    assert_eq!((inputs.done, inputs.low), (0, 0b111));
    // Axis 1 done (a zero-step segment, consumed at its load), axis 0's
    // FIFO above its low mark (two segments it does not run).
    let mut pulses = pulses;
    let map = crate::regmap::pulse_bank(AXES, 32);
    let ax = |i: u32, name: &str| map.array("AX").address(i, name);
    let mut script = vec![(ax(0, "SEG_PUSH"), 0), (ax(0, "SEG_PUSH"), 0)];
    for name in ["SEG_STEPS", "SEG_RATE", "SEG_ACCEL", "SEG_JERK", "SEG_PUSH"] {
        script.push((ax(1, name), 0));
    }
    script.push((ax(1, "CTRL"), 0b100));
    script.push((map.register("RUN").offset, 0b010));
    for (addr, value) in script {
        pulses.clock(false, &BusCycle::write(addr, value), false);
    }
    for _ in 0..10 {
        pulses.clock(false, &BusCycle::default(), false);
    }
    let inputs = SafetyInputs::from_pulses(true, pins, &pulses);
    assert_eq!((inputs.done, inputs.low), (0b010, 0b110));
}

#[test]
fn clock_with_pulses_passes_the_neighbours_signals_to_their_causes() {
    let mut pulses = PulseBank::new(AXES, 32);
    let mut io = SafetyIo::new(AXES, 1);
    let idle = BusCycle::default();
    let pins = MachinePins::default();
    io.clock_with_pulses(
        &mut pulses,
        false,
        (&idle, false),
        &idle,
        (true, pins),
        (0b001, 0b010, true, true),
    );
    let map = regmap::safety_io(AXES);
    let reg = |io: &SafetyIo, name: &str| io.read_value(map.register(name).offset);
    assert_eq!(reg(&io, "COUNTER_CAUSE"), 0b001 | 0b010 << 16);
    assert_eq!(reg(&io, "CAUSE"), 0b1100, "DOORBELL and SERVO_TICK");
    assert_eq!((reg(&io, "DONE_CAUSE"), reg(&io, "LOW_CAUSE")), (0, 0b111));
    io.clock_with_pulses(
        &mut pulses,
        true,
        (&idle, false),
        &idle,
        (true, pins),
        (0, 0, false, false),
    );
    assert_eq!(io, SafetyIo::new(AXES, 1), "reset");
}

#[test]
fn reset_restores_every_register_and_keeps_the_filter_tick() {
    let tick = 3;
    let mut b = Bench::new();
    b.io = SafetyIo::new(AXES, tick);
    b.idle();
    b.idle();
    b.write("CLEAR", 1);
    for (name, value) in [
        ("ENABLE", 0b11),
        ("WDT_TIMEOUT", 9),
        ("IRQ_CTRL", 1),
        ("GPO_SAFE", 7),
    ] {
        b.write(name, value);
    }
    b.inputs.doorbell = true;
    b.inputs.machine.limit_pos = 1;
    b.idle();
    b.io.clock(true, &BusCycle::default(), &b.inputs);
    assert_eq!(b.dump(), Bench::new().dump(), "registers after reset");
    assert!(b.io.halted() && b.io.drive_enable() == 0);
    assert_eq!(b.io, SafetyIo::new(AXES, tick), "every flip-flop");
}

/// The block's GPO pins are its general-purpose outputs: push-pull, they
/// drive GPO_VALUE once the card runs.
#[test]
fn the_gpo_pins_drive_gpo_value() {
    let mut b = Bench::released();
    b.write("GPO_VALUE", 0b1010);
    assert_eq!(
        b.io.gpo_pins(),
        GpoPins {
            out: 0b1010,
            oe: 0xffff
        }
    );
}
