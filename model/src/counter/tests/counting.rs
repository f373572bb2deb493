//! Counting modes, errors, latency, LOAD, wrap-around and CTRL.

use super::*;
use crate::regmap::mode;

#[test]
fn params_are_checked() {
    assert_eq!(CounterParams::new(2, 1).count_mask(), 3);
    assert_eq!(CounterParams::new(32, 8).count_mask(), u32::MAX);
    assert_eq!(CounterParams::new(4, 2).err_max(), 3);
    let e = std::panic::catch_unwind(|| CounterParams::new(33, 8)).unwrap_err();
    assert_eq!(
        e.downcast_ref::<String>().unwrap(),
        "counter width = 33 out of range 2..=32"
    );
    let e = std::panic::catch_unwind(|| CounterParams::new(28, 0)).unwrap_err();
    assert_eq!(
        e.downcast_ref::<String>().unwrap(),
        "err_bits = 0 out of range 1..=8"
    );
}

#[test]
fn x4_full_cycle_counts_plus_and_minus_four() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::X4));
    r.walk(&FWD);
    assert_eq!(r.count(), 4);
    r.walk(&BWD);
    assert_eq!(r.count(), 0);
    r.walk(&BWD);
    assert_eq!(r.count(), -4);
    assert_eq!(r.ch.state().count, (1 << 28) - 4);
    assert!(!r.ch.state().err);
}

#[test]
fn x4_counts_each_gray_step() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::X4));
    for (i, &ab) in FWD.iter().enumerate() {
        r.walk(&[ab]);
        assert_eq!(r.count(), i as i64 + 1);
    }
}

#[test]
fn x2_and_x1_count_two_and_one_per_cycle() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::X2));
    r.walk(&FWD);
    assert_eq!(r.count(), 2);
    r.walk(&BWD);
    r.walk(&BWD);
    assert_eq!(r.count(), -2);

    let mut r = Rig::new(28, ctrl_field("MODE", mode::X1));
    // X1 counts only 00 -> 10 up and 10 -> 00 down.
    r.walk(&FWD[..1]);
    assert_eq!(r.count(), 1);
    r.walk(&FWD[1..]);
    assert_eq!(r.count(), 1);
    r.walk(&BWD);
    assert_eq!(r.count(), 0);
    r.walk(&BWD);
    assert_eq!(r.count(), -1);
}

/// X2 counts the transitions that change A, and only those: in the
/// forward cycle 00 → 10 → 11 → 01 → 00 the first and the third.
#[test]
fn x2_counts_on_the_edges_of_a() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::X2));
    let mut counts = Vec::new();
    for &ab in &FWD {
        r.walk(&[ab]);
        counts.push(r.count());
    }
    assert_eq!(counts, vec![1, 1, 2, 2]);
    let mut counts = Vec::new();
    for &ab in &BWD {
        r.walk(&[ab]);
        counts.push(r.count());
    }
    assert_eq!(counts, vec![2, 1, 1, 0], "backward: 00 → 01 → 11 → 10 → 00");
}

#[test]
fn x4_x2_x1_agree_on_position() {
    let mut path = cycles(&FWD, 3);
    path.extend(cycles(&BWD, 1));
    path.extend(&FWD[..3]);
    path.extend(&BWD[1..]); // back to 00: net +2 cycles
    path.extend(cycles(&BWD, 5));
    path.extend(cycles(&FWD, 1)); // net -2 cycles
    let mut got = Vec::new();
    for m in [mode::X4, mode::X2, mode::X1] {
        let mut r = Rig::new(28, ctrl_field("MODE", m));
        r.walk(&path);
        got.push(r.count());
    }
    assert_eq!(got, vec![-8, -4, -2]);
}

#[test]
fn reverse_negates_every_mode() {
    let gray = cycles(&FWD, 2);
    // Pulses on A only, B low: up in both pulse modes.
    let pulses = [(true, false), (false, false), (true, false), (false, false)];
    let cases: [(u32, &[Ab], i64); 5] = [
        (mode::X4, &gray, 8),
        (mode::X2, &gray, 4),
        (mode::X1, &gray, 2),
        (mode::PULSE_DIR, &pulses, 2),
        (mode::CW_CCW, &pulses, 2),
    ];
    for (m, path, expect) in cases {
        let mut r = Rig::new(28, ctrl_field("MODE", m));
        r.walk(path);
        let mut rev = Rig::new(28, ctrl_field("MODE", m) | ctrl_field("REVERSE", 1));
        rev.walk(path);
        assert_eq!(r.count(), expect, "mode {m}");
        assert_eq!(rev.count(), -expect, "mode {m}");
    }
}

#[test]
fn pulse_direction_counts_rising_a_by_level_of_b() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::PULSE_DIR));
    // Three pulses with B = 0: up.
    r.walk(&[
        (true, false),
        (false, false),
        (true, false),
        (false, false),
        (true, false),
        (false, false),
    ]);
    assert_eq!(r.count(), 3);
    // B goes high on its own: no count. Then two pulses down.
    r.walk(&[(false, true)]);
    assert_eq!(r.count(), 3);
    r.walk(&[(true, true), (false, true), (true, true), (false, true)]);
    assert_eq!(r.count(), 1);
    // A falling never counts; the direction seen is B at the rising edge.
    r.walk(&[(true, false), (false, true)]);
    assert_eq!(r.count(), 2);
    assert!(!r.ch.state().err);
}

#[test]
fn cw_ccw_counts_and_simultaneous_rise_does_not() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::CW_CCW));
    r.walk(&[(true, false), (false, false), (true, false), (false, false)]);
    assert_eq!(r.count(), 2);
    r.walk(&[(false, true), (false, false)]);
    assert_eq!(r.count(), 1);
    // Both rise in the same clock: nothing.
    r.walk(&[(true, true), (false, false)]);
    assert_eq!(r.count(), 1);
    // A rises while B is already high: up.
    r.walk(&[(false, true), (true, true)]);
    assert_eq!(r.count(), 1);
    assert!(!r.ch.state().err, "CW/CCW is not a quadrature mode");
}

#[test]
fn illegal_transition_latches_error_and_saturates() {
    let ctrl = ctrl_field("MODE", mode::X4) | ctrl_field("ERR_EN", 1);
    let mut r = Rig::at(28, 2, ctrl, (false, false, false));
    let mut expect = [1, 2, 3, 3, 3].into_iter();
    for ab in [
        (true, true),
        (false, false),
        (true, true),
        (false, false),
        (true, true),
    ] {
        r.walk(&[ab]);
        assert_eq!(r.count(), 0, "an illegal transition never counts");
        assert!(r.ch.state().err);
        assert_eq!(r.ch.state().err_count, expect.next().unwrap());
    }
    // A legal step after it counts normally: (1,1) -> (0,1) is forward.
    r.walk(&[(false, true)]);
    assert_eq!(r.count(), 1);
    assert_eq!(r.ch.state().err_count, 3);
    assert_eq!(status_field("ERR_COUNT", r.ch.status()), 3);
    assert_eq!(status_field("ERR", r.ch.status()), 1);

    r.cmd("CLEAR_STATUS");
    assert!(!r.ch.state().err);
    assert_eq!(r.ch.state().err_count, 0);
    assert_eq!(r.count(), 1, "CLEAR_STATUS leaves the count alone");
}

#[test]
fn illegal_without_err_en_latches_nothing() {
    for m in [mode::X4, mode::X2, mode::X1] {
        let mut r = Rig::new(28, ctrl_field("MODE", m));
        r.walk(&[(true, true), (false, false), (true, true)]);
        assert_eq!(r.count(), 0);
        assert!(!r.ch.state().err);
        assert_eq!(r.ch.state().err_count, 0);
    }
}

#[test]
fn reserved_modes_never_count_nor_raise_errors() {
    for m in 5..=7 {
        let mut r = Rig::new(28, ctrl_field("MODE", m) | ctrl_field("ERR_EN", 1));
        r.walk(&cycles(&FWD, 2));
        r.walk(&[(true, true), (false, false), (true, false)]);
        assert_eq!(r.count(), 0, "mode {m}");
        assert!(!r.ch.state().err, "mode {m}");
    }
}

#[test]
fn pin_to_count_latency_and_one_step_per_clock() {
    let mut r = Rig::new(28, ctrl_field("MODE", mode::X4));
    r.pins.0 = true;
    let mut seen = Vec::new();
    for _ in 0..PIN_TO_COUNT {
        seen.push(r.count());
        r.idle(1);
    }
    seen.push(r.count());
    assert_eq!(seen, vec![0, 0, 0, 0, 0, 1]);
    // Filter setting F delays by F more clocks.
    let f = 6;
    let mut r = Rig::new(28, ctrl_field("FILTER_AB", f));
    r.pins.0 = true;
    r.idle(PIN_TO_COUNT + f as usize - 1);
    assert_eq!(r.count(), 0);
    r.idle(1);
    assert_eq!(r.count(), 1);
}

#[test]
fn up_q_reaches_count_one_clock_later() {
    let mut ch = Channel::new(CounterParams::new(28, 8));
    let mut s = ChannelState::default();
    s.fa.level = true; // 00 -> 10: forward
    ch.set_state(s);
    assert_eq!(ch.step(&ChannelInputs::default()), (true, false));
    ch.clock(&ChannelInputs::default());
    assert!(ch.state().up_q);
    assert_eq!(ch.state().count, 0);
    ch.clock(&ChannelInputs::default());
    assert!(!ch.state().up_q);
    assert_eq!(ch.state().count, 1);
    // 00 -> 01 is backward: down_q, and the count falls back to 0.
    let mut s = ChannelState::default();
    s.fb.level = true;
    ch.set_state(s);
    assert_eq!(ch.step(&ChannelInputs::default()), (false, true));
    ch.clock(&ChannelInputs::default());
    assert!(ch.state().down_q);
    ch.set_state(ChannelState::default());
    assert_eq!(
        ch.step(&ChannelInputs::default()),
        (false, false),
        "no move"
    );
}

#[test]
fn load_takes_preset_modulo_two_to_the_w() {
    let mut r = Rig::new(4, 0);
    r.preset = 0xffff_fffa;
    r.cmd("LOAD");
    assert_eq!(r.ch.state().count, 0xa);
    assert_eq!(r.count(), -6);
    let mut r = Rig::new(28, 0);
    r.preset = 0x1234_5678;
    r.cmd("LOAD");
    assert_eq!(r.ch.state().count, 0x0234_5678);
}

#[test]
fn count_wraps_at_both_ends() {
    for w in [4u32, 28, 32] {
        let max = CounterParams::new(w, 8).count_mask();
        let mut ch = Channel::new(CounterParams::new(w, 8));
        ch.set_state(ChannelState {
            count: max,
            up_q: true,
            ..Default::default()
        });
        ch.clock(&ChannelInputs::default());
        assert_eq!(ch.state().count, 0, "W = {w}");
        ch.set_state(ChannelState {
            down_q: true,
            ..*ch.state()
        });
        ch.clock(&ChannelInputs::default());
        assert_eq!(ch.state().count, max, "W = {w}");
    }
    // Through the pins at W = 4: 7 + 1 reads as -8, -8 - 1 reads as 7.
    let mut r = Rig::new(4, ctrl_field("MODE", mode::X4));
    r.preset = 7;
    r.cmd("LOAD");
    r.walk(&FWD[..1]);
    assert_eq!(r.ch.state().count, 8);
    assert_eq!(r.count(), -8);
    r.walk(&[(false, false)]);
    assert_eq!(r.count(), 7);
    r.walk(&cycles(&FWD, 4));
    assert_eq!(r.count(), 7, "16 steps wrap a 4-bit counter exactly once");
}

#[test]
fn sign_extension_and_wrap() {
    assert_eq!(sign_extend(0x8, 4), 0xffff_fff8);
    assert_eq!(sign_extend(0x7, 4), 7);
    assert_eq!(sign_extend(0x0800_0000, 28), 0xf800_0000);
    assert_eq!(sign_extend(0x07ff_ffff, 28), 0x07ff_ffff);
    assert_eq!(sign_extend(0x8000_0000, 32), 0x8000_0000);
    assert_eq!(sign_extend(0x2, 2), 0xffff_fffe);
    assert_eq!(wrap(0x1234_5678, 28), 0x0234_5678);
    assert_eq!(wrap(0x1234_5678, 32), 0x1234_5678);
}

#[test]
fn ctrl_write_is_masked_and_reads_back_live() {
    let mut ch = Channel::new(CounterParams::new(28, 8));
    ch.clock(&ChannelInputs {
        ctrl_write: Some(u32::MAX),
        ..Default::default()
    });
    let writable = regmap::counter_bank(1, 28)
        .array("CH")
        .register("CTRL")
        .writable_mask();
    assert_eq!(ch.state().ctrl, writable);
    assert_eq!(ch.read("CTRL"), writable);
    assert_eq!(ch.read("CMD"), 0);
}
