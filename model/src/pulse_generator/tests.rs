//! Tests of the axis, its step timing and the move engine.

use super::*;

fn timing(l: u32, s: u32, su: u32, h: u32) -> StepTiming {
    StepTiming {
        step_len: l,
        step_space: s,
        dir_setup: su,
        dir_hold: h,
    }
}

#[test]
fn half_clock_rate_gives_a_step_every_other_clock() {
    let mut g = PulseGenerator::new();
    let inp = PulseInputs {
        enable: true,
        halt: false,
        rate: i32::MIN,
        timing: timing(1, 1, 1, 1),
    };
    assert_eq!(inp.rate, i32::MIN);
    let mut rises = 0;
    let mut last = false;
    for _ in 0..1000 {
        g.clock(&inp, false);
        let (s, _) = g.outputs();
        rises += u32::from(s && !last);
        last = s;
    }
    // Negative full rate: 500 commanded, the first one after a
    // direction set-up of one clock.
    assert!((498..=500).contains(&rises), "{rises}");
    assert_eq!(g.position as i32, -(rises as i32));
}

#[test]
fn pulses_honour_the_timing() {
    let t = timing(3, 2, 4, 5);
    let mut g = PulseGenerator::new();
    let mut hist = Vec::new();
    for k in 0..4000 {
        let rate = if (k / 1000) % 2 == 0 {
            1 << 29
        } else {
            -(1 << 29)
        };
        g.clock(
            &PulseInputs {
                enable: k < 3500,
                halt: false,
                rate,
                timing: t,
            },
            false,
        );
        hist.push(g.outputs());
    }
    // Runs of S1 high >= 3, low >= 2; S2 changes only with S1 low for
    // >= 5 clocks before and >= 4 clocks before the next rise.
    let mut k = 0;
    while k < hist.len() {
        let (s, _) = hist[k];
        let mut j = k;
        while j < hist.len() && hist[j].0 == s {
            j += 1;
        }
        if k > 0 && j < hist.len() {
            assert!(
                j - k >= if s { 3 } else { 2 },
                "run of {s} at {k}: {}",
                j - k
            );
        }
        k = j;
    }
    for k in 1..hist.len() {
        if hist[k].1 != hist[k - 1].1 {
            assert!(!hist[k].0 && (k.saturating_sub(5)..k).all(|j| !hist[j].0));
            let next_rise = (k..hist.len()).find(|&j| hist[j].0);
            if let Some(r) = next_rise {
                assert!(r - k >= 4);
            }
        }
    }
    assert_eq!(g.timer.state().pending, 0);
    assert!(!g.outputs().0);
}

/// SEG_* writes fill the tail slot; while the FIFO is full they are
/// dropped, and a field not written keeps the slot's old contents.
#[test]
fn segment_writes_go_to_the_tail_slot_and_are_dropped_when_full() {
    use SegmentField::*;
    let mut e = MoveEngine::default();
    let write = |e: &mut MoveEngine, f: SegmentField, v: u32| {
        e.clock_bus(false, false, false, &[(f, v)], false)
    };
    let push = |e: &mut MoveEngine| e.clock_bus(false, false, false, &[], true);
    for k in 0..SEGMENT_FIFO_DEPTH as u32 {
        write(&mut e, Steps, 5 + k);
        write(&mut e, Rate, 100 + k);
        write(&mut e, Accel, 0);
        push(&mut e);
    }
    assert_eq!(e.level(), SEGMENT_FIFO_DEPTH);
    // Full: this write is dropped and the push overflows.
    write(&mut e, Steps, 99);
    push(&mut e);
    assert!(e.overflow());
    assert_eq!(e.level(), SEGMENT_FIFO_DEPTH);
    // Run the first segment in: its slot (slot 0) frees and becomes the
    // tail, and only RATE is written into it, so its steps stay 5.
    e.clock_bus(true, false, false, &[], false);
    assert!(e.active() && e.rate() == 100, "{e:?}");
    write(&mut e, Rate, 300);
    push(&mut e);
    let wants = (1..SEGMENT_FIFO_DEPTH as u32).map(|k| (5 + k, 100 + k));
    for want in wants.chain([(5, 300)]) {
        // Finish the running segment; the next loads the next clock (its
        // copy was read while this one ran).
        // Bounded, so an engine that never ends a segment fails, not hangs.
        for _ in 0..100 {
            if !e.active() {
                break;
            }
            e.clock_bus(true, true, false, &[], false);
        }
        e.clock_bus(true, false, false, &[], false);
        assert_eq!((e.probe().remaining, e.rate() as u32), want);
    }
    assert_eq!(e.level(), 0);
}

/// The running rate by hand: SEG_ACCEL and SEG_JERK carry 16 fraction
/// bits each, and the NCO's rate is the rate's floor (toward −∞).
#[test]
fn ramps_have_fraction_bits() {
    let run = |seg: Segment, clocks: usize| {
        let mut e = MoveEngine::default();
        e.clock(true, false, false, Some(seg));
        for _ in 0..=SEGMENT_FETCH_CLOCKS {
            e.clock(true, false, false, None);
        }
        assert!(e.active(), "{seg:?} not loaded");
        for _ in 0..clocks {
            e.clock(true, false, true, None);
        }
        e.rate()
    };
    let seg = |rate, accel, jerk| Segment {
        steps: 5,
        rate,
        accel,
        jerk,
    };
    // A load holds half an LSB, so the floors round to nearest: a quarter
    // rate LSB per clock gives 5.5, 5.75, 6.0.
    assert_eq!(run(seg(5, 1 << 14, 0), 1), 5);
    assert_eq!(run(seg(5, 1 << 14, 0), 2), 6);
    // Half an LSB per clock (with the half from the acceleration's own
    // load fraction, whose floor is 0): 5.5, 6.0.
    assert_eq!(run(seg(5, 1 << 15, 0), 1), 6);
    // Backwards the register is −5 + 0.5: −5.0 after one clock, −5.5 (so
    // −6) after two.
    assert_eq!(run(seg(-5, -(1 << 15), 0), 1), -5);
    assert_eq!(run(seg(-5, -(1 << 15), 0), 2), -6);
    // Jerk 3 accel LSBs per clock: the rate after k clocks is
    // ⌊5.5 + 3·k(k−1)/2 / 2^16⌋, 6 first at k = 149 (148·147 < 21 846 <=
    // 149·148).
    assert_eq!(run(seg(5, 0, 3 << 16), 148), 5);
    assert_eq!(run(seg(5, 0, 3 << 16), 149), 6);
    // Half an accel LSB of jerk: the accel's whole parts are ⌊(i+1)/2⌋,
    // summing to ⌊k²/4⌋ >= 2^15 first at k = 363.
    assert_eq!(run(seg(5, 0, 1 << 15), 362), 5);
    assert_eq!(run(seg(5, 0, 1 << 15), 363), 6);
}

/// A segment pushed into an empty FIFO is running after the fifth edge
/// after its push: SEGMENT_FETCH_CLOCKS edges copy it out of the RAM (one
/// read per field, each a clock behind its address), the next loads it.
#[test]
fn a_segment_loads_four_clocks_after_it_reaches_the_head() {
    let seg = Segment {
        steps: 3,
        rate: 7,
        ..Default::default()
    };
    let mut e = MoveEngine::default();
    e.clock(true, false, false, Some(seg));
    let mut clocks = 0;
    while !e.active() {
        assert!(clocks < 10, "never loaded");
        e.clock(true, false, false, None);
        clocks += 1;
    }
    assert_eq!(clocks, SEGMENT_FETCH_CLOCKS + 1);
    assert_eq!((e.probe().remaining, e.rate()), (3, 7));
}

/// Reset clears the FIFO's bookkeeping, not its RAM: after a reset, a
/// slot whose fields are not written again carries its old words.
#[test]
fn reset_keeps_the_segment_slots() {
    use SegmentField::*;
    let mut e = MoveEngine::default();
    e.clock(
        false,
        false,
        false,
        Some(Segment {
            steps: 9,
            rate: 4,
            accel: 1,
            jerk: 1,
        }),
    );
    e.reset();
    assert_eq!(e.probe(), MoveEngineProbe::default());
    e.clock_bus(true, false, false, &[(Rate, 2)], false);
    e.clock_bus(true, false, false, &[], true);
    for _ in 0..=SEGMENT_FETCH_CLOCKS {
        e.clock(true, false, false, None);
    }
    assert_eq!((e.probe().remaining, e.rate()), (9, 2));
}

/// The QUADRATURE output's Gray code: position mod 4 gives A/B = 00, 10,
/// 11, 01, so each step up or down changes exactly one of them and A
/// leads B going up.
#[test]
fn quadrature_is_the_gray_phase_of_the_position() {
    let table = [(false, false), (true, false), (true, true), (false, true)];
    for position in 0..16u32 {
        assert_eq!(
            pulse_bank::quadrature(position),
            table[(position % 4) as usize],
            "position {position}"
        );
        let (a, b) = pulse_bank::quadrature(position);
        let (na, nb) = pulse_bank::quadrature(position.wrapping_add(1));
        assert_eq!(
            u8::from(a != na) + u8::from(b != nb),
            1,
            "one change, {position}"
        );
    }
    assert_eq!(pulse_bank::quadrature(u32::MAX), (false, true));
}
