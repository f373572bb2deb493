//! The move engine against docs/pulse_generator.md: the segment FIFO and
//! its copy of the head, loading, ramps with fraction bits, jerk, braking.

use super::*;

fn seg(steps: u32, rate: i32, accel: i32, jerk: i32) -> Segment {
    Segment {
        steps,
        rate,
        accel,
        jerk,
    }
}

/// Clocks with RUN high and the NCO idle until a segment runs.
fn load(e: &mut MoveEngine) -> usize {
    let mut clocks = 0;
    while !e.active() {
        assert!(clocks < 20, "never loaded: {e:?}");
        e.clock(true, false, false, None);
        clocks += 1;
    }
    clocks
}

/// A 48-bit register value as the docs define it: modulo 2^48, two's
/// complement.
fn wrap48(x: i128) -> i128 {
    let m = 1i128 << 48;
    let x = x.rem_euclid(m);
    if x >= m / 2 {
        x - m
    } else {
        x
    }
}

/// The copy of the head is complete 4 edges after the push that made it
/// the head, one field read a clock; it waits for RUN, loads at the next
/// edge with RUN, and nothing loads from an empty FIFO.
#[test]
fn the_head_copy_takes_four_edges_and_waits_for_run() {
    let mut e = MoveEngine::default();
    for _ in 0..10 {
        e.clock(true, false, false, None);
        assert!(
            !e.active() && !e.probe().staged && e.probe().fetch == 0,
            "{e:?}"
        );
    }
    e.clock(false, false, false, Some(seg(3, 7, 0, 0)));
    let mut progress = Vec::new();
    for _ in 0..SEGMENT_FETCH_CLOCKS {
        assert!(!e.probe().staged, "{e:?}");
        e.clock(false, false, false, None);
        progress.push((e.probe().fetch, e.probe().staged));
    }
    assert_eq!(progress, [(1, false), (2, false), (3, false), (0, true)]);
    for _ in 0..30 {
        e.clock(false, false, false, None);
        assert!(!e.active() && e.probe().staged && e.level() == 1, "{e:?}");
    }
    e.clock(true, false, false, None);
    assert!(e.active() && e.level() == 0 && !e.probe().staged, "{e:?}");
    assert_eq!((e.probe().remaining, e.rate()), (3, 7));
}

/// A segment ends after commanding exactly SEG_STEPS steps (a zero-step one
/// at its load); the next loads at the first edge after that once its copy,
/// begun at the load, is complete: at once after a segment of at least
/// SEGMENT_FETCH_CLOCKS clocks, with the NCO at rate 0 otherwise. DONE is
/// set when the last pushed segment has ended, and a push clears it.
#[test]
fn segments_end_on_their_steps_and_follow_once_copied() {
    let mut cases = 0;
    for steps in 0..8u32 {
        let mut e = MoveEngine::default();
        e.clock(false, false, false, Some(seg(steps, 10, 0, 0)));
        e.clock(false, false, false, Some(seg(2, 20, 0, 0)));
        // The first copy is complete; with RUN the first segment loads.
        for _ in 0..SEGMENT_FETCH_CLOCKS {
            e.clock(false, false, false, None);
        }
        e.clock(true, false, false, None);
        assert_eq!(e.level(), 1, "steps {steps}");
        let mut rates = Vec::new();
        let mut commanded = 0;
        while e.rate() != 20 {
            assert!(rates.len() < 20, "steps {steps}: {rates:?}");
            assert!(!e.done(), "steps {steps}: one still queued");
            rates.push(e.rate());
            commanded += u32::from(e.active());
            e.clock(true, e.active(), false, None);
        }
        assert_eq!(e.rate(), 20, "steps {steps}");
        assert_eq!(commanded, steps, "steps {steps}: {rates:?}");
        // Clocks from the first load to the second: max(steps, 4) + 1.
        let mut want = vec![10; steps as usize];
        want.resize(steps.max(SEGMENT_FETCH_CLOCKS as u32) as usize + 1, 0);
        assert_eq!(rates, want, "steps {steps}");
        e.clock(true, true, false, None);
        assert!(!e.done(), "steps {steps}: one step left");
        e.clock(true, true, false, None);
        assert!(
            e.done() && !e.active() && e.level() == 0,
            "steps {steps}: {e:?}"
        );
        e.clock(true, false, false, None);
        assert!(e.done(), "steps {steps}: DONE is sticky");
        e.clock(false, false, false, Some(seg(1, 1, 0, 0)));
        assert!(!e.done(), "steps {steps}: a push clears DONE");
        cases += 1;
    }
    assert_eq!(cases, 8);
}

/// A lone zero-step segment is consumed at its load and sets DONE.
#[test]
fn a_lone_zero_step_segment_is_done_at_its_load() {
    let mut e = MoveEngine::default();
    e.clock(true, false, false, Some(seg(0, 50, 0, 0)));
    for clock in 0..20 {
        assert_eq!(e.rate(), 0, "clock {clock}");
        e.clock(true, false, false, None);
        assert!(!e.active(), "clock {clock}");
        if e.level() == 0 {
            assert!(e.done(), "clock {clock}: {e:?}");
            return;
        }
    }
    panic!("never consumed: {e:?}");
}

/// FIFO_LEVEL counts pushes accepted minus loads, up to 64; a push into a
/// full FIFO is dropped and sets OVERFLOW until it is cleared.
#[test]
fn level_and_overflow_follow_pushes_and_loads() {
    let mut e = MoveEngine::default();
    for k in 0..SEGMENT_FIFO_DEPTH {
        assert_eq!(e.level(), k);
        e.clock(false, false, false, Some(seg(1, 1, 0, 0)));
        assert!(!e.overflow(), "push {k}");
    }
    for k in 0..3 {
        e.clock(false, false, false, Some(seg(1, 1, 0, 0)));
        assert_eq!(
            (e.level(), e.overflow()),
            (SEGMENT_FIFO_DEPTH, true),
            "push {k} into full"
        );
    }
    e.clock(false, false, false, None);
    assert!(e.overflow(), "sticky");
    e.clear_overflow();
    assert!(!e.overflow());
    load(&mut e);
    assert_eq!(e.level(), SEGMENT_FIFO_DEPTH - 1);
    e.clock(true, false, false, Some(seg(1, 1, 0, 0)));
    assert_eq!((e.level(), e.overflow()), (SEGMENT_FIFO_DEPTH, false));
}

/// Pushes `count` segments writing `fields` of `make(k)`, then runs them
/// all out; returns each segment as it loaded (steps, rate, accel
/// register, jerk).
fn lap(
    e: &mut MoveEngine,
    fields: &[SegmentField],
    make: impl Fn(u32) -> Segment,
) -> Vec<(u32, i32, u64, u32)> {
    for k in 0..SEGMENT_FIFO_DEPTH as u32 {
        let s = make(k);
        let writes: Vec<_> = fields
            .iter()
            .map(|&f| match f {
                SegmentField::Steps => (f, s.steps),
                SegmentField::Rate => (f, s.rate as u32),
                SegmentField::Accel => (f, s.accel as u32),
                SegmentField::Jerk => (f, s.jerk as u32),
            })
            .collect();
        e.clock_bus(false, false, false, &writes, true);
    }
    let mut loaded = Vec::new();
    for clock in 0.. {
        assert!(clock < 1000, "the lap never drained: {e:?}");
        if e.level() == 0 && !e.active() {
            break;
        }
        if e.active() {
            e.clock(true, true, false, None);
        } else {
            e.clock(true, false, false, None);
            if e.active() {
                let p = e.probe();
                loaded.push((p.remaining, e.rate(), p.accel, p.jerk));
            }
        }
    }
    loaded
}

/// A field not written keeps its slot's word from the last lap; a jerk not
/// written is the one written two laps (128 pushes) before, also across a
/// reset, since reset clears pointers, not RAM.
#[test]
fn unwritten_fields_keep_the_ram_a_jerk_the_one_two_laps_back() {
    use SegmentField::*;
    let accel_register = |a: i32| ((i64::from(a) << 16) + (1 << 15)) as u64 & ((1 << 48) - 1);
    let mut e = MoveEngine::default();
    let first = lap(&mut e, &[Steps, Rate, Accel, Jerk], |k| {
        seg(1, 100 + k as i32, -(k as i32), 1000 + k as i32)
    });
    let second = lap(&mut e, &[Steps, Rate, Accel, Jerk], |k| {
        seg(2, 200 + k as i32, 50 + k as i32, -2000 - k as i32)
    });
    e.reset();
    let third = lap(&mut e, &[Steps], |_| seg(3, 0, 0, 0));
    assert_eq!((first.len(), second.len(), third.len()), (64, 64, 64));
    for k in 0..64 {
        let i = k as i32;
        let want = [
            (1, 100 + i, accel_register(-i), 1000 + k as u32),
            (2, 200 + i, accel_register(50 + i), (-2000 - i) as u32),
            (3, 200 + i, accel_register(50 + i), 1000 + k as u32),
        ];
        assert_eq!(
            [first[k], second[k], third[k]],
            want,
            "segment {k} of each lap"
        );
    }
}

/// Every advancing clock r += ⌊a/2^16⌋ and a += SEG_JERK, both modulo
/// 2^48 two's complement, from r = SEG_RATE·2^16 + 2^15 and a = SEG_ACCEL·
/// 2^16 + 2^15; the NCO runs at ⌊r/2^16⌋. A clock that does not advance
/// changes neither.
#[test]
fn the_running_ramp_follows_the_documented_sums() {
    let segments = [
        seg(9, 5, 1 << 14, 0),
        seg(9, -5, -(1 << 15), 0),
        seg(9, 1000, -7, 3 << 16),
        seg(9, 0, 0, -1),
        seg(9, -123_456, 98_765, -(1 << 20)),
        seg(9, 1 << 30, -(1 << 30), 12_345),
        // These wrap the 48-bit registers within the run.
        seg(9, i32::MAX, i32::MAX, i32::MAX),
        seg(9, i32::MIN, i32::MIN, i32::MIN),
        seg(9, i32::MIN, -1, i32::MIN),
    ];
    let mut cases = 0;
    for s in segments {
        let mut e = MoveEngine::default();
        e.clock(true, false, false, Some(s));
        load(&mut e);
        let mut r = i128::from(s.rate) * (1 << 16) + (1 << 15);
        let mut a = i128::from(s.accel) * (1 << 16) + (1 << 15);
        for clock in 0..400 {
            let p = e.probe();
            let got = (e.rate(), p.rate, p.accel, p.jerk);
            let want = (
                (r >> 16) as i32,
                r.rem_euclid(1 << 48) as u64,
                a.rem_euclid(1 << 48) as u64,
                s.jerk as u32,
            );
            assert_eq!(got, want, "{s:?}, clock {clock}");
            let advancing = clock % 3 != 2;
            if advancing {
                r = wrap48(r + a.div_euclid(1 << 16));
                a = wrap48(a + i128::from(s.jerk));
            }
            e.clock(true, false, advancing, None);
        }
        cases += 1;
    }
    assert_eq!(cases, segments.len());
}

/// With SEG_JERK = 0 the rate after k advancing clocks is
/// ⌊(SEG_RATE·2^16 + 2^15 + k·SEG_ACCEL) / 2^16⌋.
#[test]
fn without_jerk_the_rate_has_a_closed_form() {
    let mut cases = 0;
    for (rate, accel) in [
        (0, 1),
        (7, 40_000),
        (-7, -40_000),
        (1 << 20, -3),
        (-50, 1 << 16),
    ] {
        let mut e = MoveEngine::default();
        e.clock(true, false, false, Some(seg(1, rate, accel, 0)));
        load(&mut e);
        for k in 0..1000i64 {
            let want = (i64::from(rate) * (1 << 16) + (1 << 15) + k * i64::from(accel)) >> 16;
            assert_eq!(
                i64::from(e.rate()),
                want,
                "rate {rate}, accel {accel}, k {k}"
            );
            e.clock(true, false, true, None);
        }
        cases += 1;
    }
    assert_eq!(cases, 5);
}

/// A decelerating stop from rate r with DECEL = D: the acceleration loads as
/// SEG_ACCEL = ∓D against r's sign; every advancing clock the rate takes
/// it; the NCO runs at the rate's whole part while that is nonzero and
/// against the acceleration, at 0 in the clock where it is not, and BRAKING
/// ends at the edge after that clock. No segment loads while braking.
#[test]
fn braking_ramps_the_rate_down_and_ends_on_zero_or_reversal() {
    let brakes = [
        (1000, 10 << 16),
        (1005, 10 << 16),
        (-1000, 10 << 16),
        (-1005, 10 << 16),
        (5000, 12_345),
        (-(1 << 30), (1 << 31) - 1),
        (i32::MAX, 1 << 30),
    ];
    let mut cases = 0;
    for (rate, decel) in brakes {
        let mut e = MoveEngine::default();
        e.clock(true, false, false, None);
        e.brake(false, rate, decel);
        let accel = if rate < 0 {
            i64::from(decel)
        } else {
            -i64::from(decel)
        };
        let p = e.probe();
        assert_eq!(
            p.accel,
            (((accel << 16) + (1 << 15)) as u64) & ((1 << 48) - 1),
            "{rate} {decel}"
        );
        assert_eq!(
            p.rate,
            ((i64::from(rate) << 16) + (1 << 15)) as u64 & ((1 << 48) - 1)
        );
        let mut r = (i64::from(rate) << 16) + (1 << 15);
        let mut clock = 0u64;
        let mut pushed = false;
        loop {
            assert!(e.braking(), "rate {rate}, decel {decel}, clock {clock}");
            assert!(
                !e.active(),
                "rate {rate}, decel {decel}, clock {clock}: loaded"
            );
            let whole = r >> 16;
            let heading = whole != 0 && (whole < 0) != (accel < 0);
            let want = if heading { whole as i32 } else { 0 };
            assert_eq!(e.rate(), want, "rate {rate}, decel {decel}, clock {clock}");
            let advancing = clock % 4 != 3;
            if advancing {
                r += accel;
            }
            e.clock(true, false, advancing, (!pushed).then(|| seg(5, 9, 0, 0)));
            pushed = true;
            clock += 1;
            if !heading {
                break;
            }
        }
        assert!(
            !e.braking(),
            "rate {rate}, decel {decel}: still braking after {clock}"
        );
        assert!(clock > 2, "rate {rate}, decel {decel}: {clock} clocks");
        cases += 1;
    }
    assert_eq!(cases, brakes.len());
}

/// A stop while braking drops the FIFO again but does not restart the
/// brake: the rate goes on from where it was.
#[test]
fn a_stop_while_braking_does_not_restart_it() {
    let mut e = MoveEngine::default();
    e.clock(true, false, false, None);
    e.brake(false, 1000, 10 << 16);
    for _ in 0..10 {
        e.clock(true, false, true, None);
    }
    assert_eq!(e.rate(), 900);
    e.clock(false, false, true, Some(seg(4, 4, 0, 0)));
    assert_eq!((e.rate(), e.level()), (890, 1));
    e.brake(e.braking(), 5000, 1 << 16);
    assert_eq!((e.rate(), e.level(), e.braking()), (890, 0, true));
    e.clock(true, false, true, None);
    assert_eq!(e.rate(), 880);
}

/// HALT (flush) and reset end a brake at once.
#[test]
fn halt_and_reset_end_a_brake_at_once() {
    for halt in [true, false] {
        let mut e = MoveEngine::default();
        e.clock(true, false, false, None);
        e.brake(false, -1000, 1 << 16);
        e.clock(true, false, true, None);
        assert_eq!((e.rate(), e.braking()), (-999, true), "halt {halt}");
        if halt {
            e.flush();
        } else {
            e.reset();
        }
        assert_eq!((e.rate(), e.braking()), (0, false), "halt {halt}");
        e.clock(true, false, true, None);
        assert_eq!((e.rate(), e.braking()), (0, false), "halt {halt}");
    }
}

/// HALT drops the running segment and the queued ones (FIFO_LEVEL 0, DONE
/// clear); OVERFLOW, the RAM and the head pointer stay, so a slot written
/// in part after it carries its old words; reset clears every register.
#[test]
fn halt_empties_the_fifo_but_keeps_overflow_and_the_ram() {
    let mut e = MoveEngine::default();
    for k in 0..=SEGMENT_FIFO_DEPTH as u32 {
        e.clock(false, false, false, Some(seg(10 + k, 20 + k as i32, 0, 0)));
    }
    load(&mut e);
    e.clock(true, true, true, None);
    assert!(e.overflow() && e.active() && e.level() == 63, "{e:?}");
    e.flush();
    let p = e.probe();
    assert!(!p.active && p.overflow && !p.done && !p.braking, "{p:?}");
    assert_eq!(
        (p.level, p.remaining, p.staged, p.fetch, e.rate()),
        (0, 0, false, 0, 0)
    );
    for _ in 0..10 {
        e.clock(true, false, false, None);
        assert!(!e.active() && e.level() == 0, "nothing left to load");
    }
    // One load moved the head to slot 1: its steps stay, its rate is new.
    e.clock_bus(true, false, false, &[(SegmentField::Rate, 77)], true);
    assert_eq!(load(&mut e), SEGMENT_FETCH_CLOCKS + 1);
    assert_eq!((e.probe().remaining, e.rate()), (11, 77));
    e.reset();
    assert_eq!(e.probe(), MoveEngineProbe::default());
}
