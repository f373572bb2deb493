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
    for (k, steps) in [(0u32, 5u32), (1, 7)] {
        write(&mut e, Steps, steps);
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
    // Run the first segment in: a slot frees, and only RATE is
    // written into it, so its steps are the old slot's (5).
    e.clock_bus(true, false, false, &[], false);
    assert!(e.active() && e.rate() == 100, "{e:?}");
    write(&mut e, Rate, 300);
    push(&mut e);
    for want in [(7, 101), (5, 300)] {
        // Finish the running segment, then load the next.
        while e.active() {
            e.clock_bus(true, true, false, &[], false);
        }
        e.clock_bus(true, false, false, &[], false);
        assert_eq!((e.probe().2, e.rate() as u32), want);
    }
}
