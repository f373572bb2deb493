//! A long move kept streaming by the FIFO-low interrupt alone
//! (docs/safety_io.md, "Causes and the IRQ pin"): the firmware waits on
//! the IRQ pin, reads the two cause registers, refills and clears; it
//! never polls STATUS, no axis runs dry, and the move lands exactly.

use motionhdl_model::Config;
use motionhdl_testbench::checks::motion_controller::irq_refill::{steady, stream_on_irq};
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};

/// The longest run of clocks without a shaft step while the axis moved.
fn longest_pause(path: &[Vec<i32>], axis: usize) -> usize {
    let moves: Vec<usize> = (1..path.len())
        .filter(|&k| path[k][axis] != path[k - 1][axis])
        .collect();
    moves.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0)
}

#[test]
fn a_long_two_axis_move_streams_on_the_fifo_low_interrupt_alone() {
    let config = Config::default().with_axes(2).unwrap();
    let mut sys = System::<2>::on(Engine::for_scenarios(), &config);
    sys.setup();
    // 200 segments of 10 steps at one step per 40 and per 60 clocks:
    // three FIFOs' worth each, so the firmware refills several times.
    let per_axis = [steady(200, 10, 40), steady(200, 10, 60)];
    sys.path = Some(Vec::new());
    let r = stream_on_irq(&mut sys, &per_axis, 32, 1 << 21).unwrap();
    eprintln!("{r:?}");
    assert_eq!(
        r.reads,
        2 * r.interrupts,
        "two cause reads per interrupt, no polling"
    );
    for (i, &n) in r.refills.iter().enumerate() {
        // 200 segments: 64 before RUN, then 32 per refill.
        assert_eq!(n, 5, "axis {i}: refills");
    }
    sys.idle(200);
    for i in 0..2 {
        assert_eq!(sys.drives[i].position, 2000, "axis {i} on target");
    }
    for (i, (count, position)) in sys.positions().into_iter().enumerate() {
        assert_eq!((count, position), (2000, 2000), "axis {i}");
    }
    // The steps never paused: the FIFOs never ran dry between segments.
    let path = sys.path.take().unwrap();
    for (i, period) in [40, 60].into_iter().enumerate() {
        let pause = longest_pause(&path, i);
        assert!(
            pause <= period + 1,
            "axis {i}: a {pause}-clock pause at one step per {period}"
        );
    }
}

#[test]
fn a_mark_too_low_for_the_refill_runs_dry_and_is_reported() {
    // One step per 4 clocks and a mark of 1: the one segment left lasts
    // 40 clocks, a refill of 63 segments takes thousands.
    let config = Config::default().with_axes(2).unwrap();
    let mut sys = System::<2>::on(Engine::for_scenarios(), &config);
    sys.setup();
    let per_axis = [steady(200, 10, 4), steady(200, 10, 4)];
    let e = stream_on_irq(&mut sys, &per_axis, 1, 1 << 21).unwrap_err();
    assert!(e.contains("ran dry"), "{e}");
}
