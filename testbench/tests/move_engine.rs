//! The segment FIFO (block RAM): the rust-hdl move engine against the model
//! every clock, its contract, and the contract shown able to fail.

use motionhdl_model::pulse_generator::{SegmentField, SEGMENT_FETCH_CLOCKS, SEGMENT_FIFO_DEPTH};
use motionhdl_testbench::checks::move_engine::{
    self as me, EngineInputs, EngineView, FifoContract,
};

#[test]
fn move_engine_against_model_and_fifo_contract() {
    let r = me::engine_rust(60_000, 0x5eed_0018);
    r.assert_passed();
    assert_eq!(r.covered, 60_000);
}

/// Pushes one fully written segment (steps, rate) into `c`, from `level`.
fn push(c: &mut FifoContract, level: u32, steps: u32, rate: u32) -> Vec<String> {
    let mut bad = Vec::new();
    // The low-water mark is 0: FIFO_LOW means empty.
    let view = EngineView {
        level,
        status_level: level,
        status_low: level == 0,
        ..Default::default()
    };
    for (f, v) in [
        (SegmentField::Steps, steps),
        (SegmentField::Rate, rate),
        (SegmentField::Accel, rate / 2),
        (SegmentField::Jerk, rate / 4),
    ] {
        let inp = EngineInputs {
            write: Some((f, v)),
            ..Default::default()
        };
        bad.extend(c.edge(&inp, &view, &view));
    }
    let inp = EngineInputs {
        push: true,
        ..Default::default()
    };
    let after = EngineView {
        level: level + 1,
        status_level: level + 1,
        status_low: false,
        ..view
    };
    bad.extend(c.edge(&inp, &view, &after));
    bad
}

#[test]
fn the_fifo_contract_catches_broken_fifos() {
    // A level that does not count the push.
    let mut c = FifoContract::default();
    let inp = EngineInputs {
        push: true,
        ..Default::default()
    };
    let v = EngineView {
        status_low: true,
        ..Default::default()
    };
    assert!(c.edge(&inp, &v, &v).unwrap().contains("level 0 with 1"));
    // FIFO_LOW that ignores the mark.
    let mut c = FifoContract::default();
    let inp = EngineInputs {
        low_water: 3,
        ..Default::default()
    };
    let v = EngineView {
        level: 2,
        status_level: 2,
        ..Default::default()
    };
    assert!(c
        .edge(&inp, &v, &v)
        .unwrap()
        .contains("FIFO_LOW false at level 2 mark 3"));
    // Segments out of order.
    let mut c = FifoContract::default();
    assert!(push(&mut c, 0, 5, 100).is_empty());
    assert!(push(&mut c, 1, 6, 200).is_empty());
    let inp = EngineInputs {
        run: true,
        ..Default::default()
    };
    let before = EngineView {
        level: 2,
        status_level: 2,
        staged: true,
        ..Default::default()
    };
    let after = EngineView {
        level: 1,
        status_level: 1,
        active: true,
        running: me::loaded([6, 200, 100, 50]),
        ..Default::default()
    };
    assert!(c
        .edge(&inp, &before, &after)
        .unwrap()
        .contains("pushed [5, 100, 50, 25]"));
    // The right segment with its jerk (or its acceleration's fraction)
    // lost.
    let half = 1 << 15;
    for broken in [
        [5, 100 << 16 | half, 50 << 16 | half, 0],
        [5, 100 << 16 | half, 50 << 16, 25],
        [5, 100 << 16, 50 << 16 | half, 25],
    ] {
        let mut c = FifoContract::default();
        assert!(push(&mut c, 0, 5, 100).is_empty());
        let after = EngineView {
            running: broken,
            ..after
        };
        let bad = c.edge(&inp, &before, &after).unwrap();
        assert!(bad.contains("pushed [5, 100, 50, 25]"), "{bad}");
    }
    // A push into the full FIFO that does not overflow.
    let mut c = FifoContract::default();
    let depth = SEGMENT_FIFO_DEPTH as u32;
    for level in 0..depth {
        assert!(push(&mut c, level, 1, 1).is_empty());
    }
    let bad = push(&mut c, depth, 1, 1);
    assert!(
        bad.iter()
            .any(|b| b.contains("OVERFLOW false after a push into the full FIFO")),
        "{bad:?}"
    );
    // A segment that never loads.
    let mut c = FifoContract::default();
    assert!(push(&mut c, 0, 5, 100).is_empty());
    let v = EngineView {
        level: 1,
        status_level: 1,
        ..Default::default()
    };
    let waits: Vec<_> = (0..SEGMENT_FETCH_CLOCKS + 2)
        .filter_map(|_| c.edge(&inp, &v, &v))
        .collect();
    assert_eq!(waits.len(), 1, "{waits:?}");
    assert!(waits[0].contains("waited"));
    // A segment loaded while braking; and a brake that leaves the FIFO
    // level where it was.
    let mut c = FifoContract::default();
    assert!(push(&mut c, 0, 5, 100).is_empty());
    let braking = EngineView {
        braking: true,
        ..before
    };
    let bad = c.edge(&inp, &braking, &after).unwrap();
    assert!(bad.contains("a segment loaded while braking"), "{bad}");
    let mut c = FifoContract::default();
    assert!(push(&mut c, 0, 5, 100).is_empty());
    let brake = EngineInputs {
        brake: Some((1000, 1 << 16)),
        ..Default::default()
    };
    let bad = c.edge(&brake, &v, &v).unwrap();
    assert!(bad.contains("level 1 with 0 segments queued"), "{bad}");
}
