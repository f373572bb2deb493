//! The input filter.

use super::*;

#[test]
fn filter_rejects_f_clocks_and_accepts_f_plus_one() {
    for f in 0u8..=15 {
        // Drive s2 directly: a pulse of `len` clocks at s2, from the
        // idle state of setting F (`cnt` = F).
        let run = |len: u8| {
            let mut flt = InputFilter {
                cnt: f,
                ..Default::default()
            };
            let mut accepted = false;
            for t in 0..(len as usize + 20) {
                flt.s2 = t < len as usize;
                flt.clock(false, f, false, true);
                accepted |= flt.level;
                // Keep s2 under the test's control.
                flt.s1 = false;
            }
            accepted
        };
        if f > 0 {
            assert!(!run(f), "F = {f}: a pulse of F clocks passed");
        }
        assert!(run(f + 1), "F = {f}: a pulse of F+1 clocks was rejected");
    }
}

#[test]
fn filter_latency_pin_to_level_is_f_plus_three() {
    for f in [0u8, 1, 7, 15] {
        let mut flt = InputFilter::default();
        let mut edges = 0;
        while !flt.level {
            flt.clock(true, f, false, true);
            edges += 1;
            assert!(edges < 40);
        }
        assert_eq!(edges, u32::from(f) + 3, "F = {f}");
        assert_eq!(flt.cnt, f, "reloaded with F on acceptance");
    }
}

#[test]
fn filter_takes_f_before_the_change_starts() {
    // Idle: cnt follows F every clock.
    let mut flt = InputFilter::default();
    flt.clock(false, 9, false, true);
    assert_eq!(flt.cnt, 9);
    flt.clock(false, 3, false, true);
    assert_eq!(flt.cnt, 3, "reloaded while s2 equals level");
    // A change starts: F is lowered to 0 mid-count, the change still
    // needs the 3 + 1 clocks of the F it started with.
    flt.s2 = true;
    flt.s1 = true;
    for left in [2, 1, 0] {
        flt.clock(true, 0, false, true);
        assert!(!flt.level);
        assert_eq!(flt.cnt, left);
    }
    flt.clock(true, 0, false, true);
    assert!(flt.level, "accepted on the fourth clock");
    assert_eq!(flt.cnt, 0, "and reloaded with the F of that clock");
    // Raised mid-count: the change is accepted after the old F too.
    let mut flt = InputFilter {
        s1: true,
        s2: true,
        level: false,
        cnt: 1,
    };
    flt.clock(true, 15, false, true);
    assert!(!flt.level);
    flt.clock(true, 15, false, true);
    assert!(flt.level);
    assert_eq!(flt.cnt, 15);
}

#[test]
fn filter_follows_s2_during_reset() {
    let mut flt = InputFilter {
        s1: true,
        s2: true,
        level: false,
        cnt: 9,
    };
    flt.clock(false, 15, true, true);
    assert_eq!(
        flt,
        InputFilter {
            s1: false,
            s2: true,
            level: true,
            cnt: 0
        }
    );
}

#[test]
fn filter_left_out_of_the_build_is_a_synchroniser_whatever_the_setting() {
    for f in [0u8, 1, 15] {
        let mut flt = InputFilter::default();
        let mut edges = 0;
        while !flt.level {
            flt.clock(true, f, false, false);
            assert_eq!(
                flt.cnt, 0,
                "F = {f}: the count of a filter left out stays 0"
            );
            edges += 1;
            assert!(edges < 40);
        }
        assert_eq!(edges, 3, "F = {f}: the latency of F = 0");
    }
}
