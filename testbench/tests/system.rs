//! The whole controller in simulation: moves planned by the
//! model's algorithms, streamed over the FSMC bus into the top (Verilated,
//! [`Engine::for_scenarios`]; the last test holds it to the rust-hdl top),
//! out through the pulse generators and selectors to simulated drives whose
//! encoders the counter bank counts, read back by the firmware.

use motionhdl_firmware::scurve::{SCurve, SCurveParams};
use motionhdl_firmware::scurve_segments::{self, EngineLimits};
use motionhdl_model::pulse_generator::Segment;
use motionhdl_model::Config;
use motionhdl_testbench::checks::motion_controller::system::{
    net_steps, plan_segments, trace_on, Engine, System,
};

const CLOCK_HZ: u32 = 50_000_000;

/// Whole-step positions of an S-curve, one per tick from rest to rest.
fn scurve_steps(distance: i64, tick_hz: u32, velocity: f64, accel: f64, jerk: f64) -> Vec<i64> {
    let p = SCurveParams::from_physical(jerk, accel, velocity, distance, f64::from(tick_hz));
    let curve = SCurve::new(p).unwrap_or_else(|e| panic!("{p:?}: {e}"));
    curve.samples().map(|s| s.steps()).collect()
}

#[test]
fn an_s_curve_move_is_counted_back_exactly_on_target() {
    // Planned as one segment per phase (SEG_JERK carries the jerk), not one
    // per servo tick.
    let target = 1000;
    let lim = EngineLimits::from_physical(2e6, 4e9, 8e13, f64::from(CLOCK_HZ));
    let plan = scurve_segments::plan(target, lim).unwrap();
    let segs = plan.segments.clone();
    assert!(segs.len() <= 7, "{segs:?}");
    assert!(segs.iter().any(|s| s.jerk != 0));
    let sys = run_on_axis_0(&segs, target);
    eprintln!(
        "S-curve: {} segments, {} clocks planned, {} clocks simulated",
        segs.len(),
        plan.clocks,
        sys.clocks
    );
}

#[test]
fn a_per_tick_s_curve_is_counted_back_exactly_on_target() {
    let tick_hz = 100_000;
    let target = 1000;
    let steps = scurve_steps(target, tick_hz, 2e6, 4e9, 8e13);
    assert_eq!(*steps.last().unwrap(), target, "the plan ends on target");
    let segs = plan_segments(&steps, CLOCK_HZ, tick_hz);
    run_on_axis_0(&segs, target);
}

/// Streams `segs` to axis 0 of the default 4-axis top and checks the
/// shaft, COUNT and POSITION land on `target` while the others stay still.
fn run_on_axis_0(segs: &[Segment], target: i64) -> System<4> {
    assert_eq!(net_steps(segs), target);
    let mut sys = System::<4>::on(Engine::for_scenarios(), &Config::default());
    sys.setup();
    let none = Vec::new();
    sys.run_move(&[segs.to_vec(), none.clone(), none.clone(), none], 400_000)
        .unwrap();
    let p = sys.positions();
    assert_eq!(sys.drives[0].position as i64, target, "shaft");
    assert_eq!(p[0], (target as i32, target as i32), "(COUNT, POSITION)");
    for (i, q) in p.iter().enumerate().skip(1) {
        assert_eq!(*q, (0, 0), "axis {i} stays still");
    }
    sys
}

#[test]
fn a_two_axis_circle_closes_and_stays_on_the_circle() {
    let config = Config::default();
    let tick_hz = 100_000;
    let (r, ticks) = (300.0f64, 200usize);
    let angle = |k: usize| std::f64::consts::TAU * k as f64 / ticks as f64;
    let x: Vec<i64> = (0..=ticks)
        .map(|k| (r * angle(k).cos()).round() as i64 - r as i64)
        .collect();
    let y: Vec<i64> = (0..=ticks)
        .map(|k| (r * angle(k).sin()).round() as i64)
        .collect();
    let (sx, sy) = (
        plan_segments(&x, CLOCK_HZ, tick_hz),
        plan_segments(&y, CLOCK_HZ, tick_hz),
    );
    assert_eq!((net_steps(&sx), net_steps(&sy)), (0, 0));
    let mut sys = System::<4>::on(Engine::for_scenarios(), &config);
    sys.setup();
    sys.path = Some(Vec::new());
    sys.run_move(&[sx, sy, Vec::new(), Vec::new()], 1_000_000)
        .unwrap();
    let p = sys.positions();
    assert_eq!((p[0], p[1]), ((0, 0), (0, 0)), "back at the start");
    let path = sys.path.take().unwrap();
    let worst = path
        .iter()
        .map(|q| ((f64::from(q[0]) + r).hypot(f64::from(q[1])) - r).abs())
        .fold(0.0, f64::max);
    let top = path.iter().map(|q| q[1]).max().unwrap();
    let bottom = path.iter().map(|q| q[1]).min().unwrap();
    eprintln!(
        "circle: {} clocks, worst radial error {worst:.2} steps",
        path.len()
    );
    assert!((top, bottom) == (300, -300), "y reached {top} and {bottom}");
    // Each axis follows its own segments; both start in one RUN write, so
    // the path stays within a step or two of the circle.
    assert!(worst <= 2.5, "radial error {worst:.2} steps");
}

#[test]
fn six_axes_follow_a_master_at_their_ratios() {
    let config = Config::new(6, 28, u64::from(CLOCK_HZ)).unwrap();
    let tick_hz = 50_000;
    let master = scurve_steps(600, tick_hz, 1e6, 2e9, 4e13);
    // (num, den): the five followers' ratios K.
    let ratios = [(1, 1), (2, 1), (-1, 1), (1, 2), (3, 2)];
    let mut per_axis = vec![plan_segments(&master, CLOCK_HZ, tick_hz)];
    for (num, den) in ratios {
        let follower: Vec<i64> = master.iter().map(|m| (m * num).div_euclid(den)).collect();
        per_axis.push(plan_segments(&follower, CLOCK_HZ, tick_hz));
    }
    let mut sys = System::<6>::on(Engine::for_scenarios(), &config);
    sys.setup();
    for (i, (num, den)) in ratios.iter().enumerate() {
        sys.track(0, i + 1, *num, *den);
    }
    sys.run_move(&per_axis, 2_000_000).unwrap();
    let p = sys.positions();
    assert_eq!(p[0], (600, 600));
    for (i, (num, den)) in ratios.iter().enumerate() {
        let want = (600 * num / den) as i32;
        assert_eq!(
            p[i + 1],
            (want, want),
            "follower {} at K = {num}/{den}",
            i + 1
        );
    }
    // The firmware streams one segment per axis per tick and every axis
    // times its own segments, so a follower may run ahead or behind within
    // a tick: the bound is one tick of its motion (K x the master's most
    // steps in a tick), in units of 1/den step.
    let per_tick = master
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .max()
        .unwrap();
    assert!(
        per_tick >= 10,
        "the master moves {per_tick} steps a tick at most"
    );
    for &(_, s, num, den, err) in sys.tracking() {
        eprintln!("follower {s} K = {num}/{den}: worst |s*den - num*m| = {err}");
        assert!(
            err <= num.abs() * per_tick,
            "follower {s} strayed {err}/{den} steps from K x master"
        );
    }
}

/// An e-stop in the middle of four S-curves: every axis stops within the
/// documented latency, no step reaches a drive after it, commanded and
/// counted positions still agree, the drives are disabled, and nothing
/// moves again until the chain is closed and firmware clears the latch.
#[test]
fn an_estop_in_the_middle_of_four_s_curves_stops_every_axis() {
    let targets = [1000i64, -800, 600, 1200];
    let lim = EngineLimits::from_physical(2e6, 4e9, 8e13, f64::from(CLOCK_HZ));
    let plans: Vec<_> = targets
        .iter()
        .map(|&t| scurve_segments::plan(t, lim).unwrap())
        .collect();
    let mut sys = System::<4>::on(Engine::for_scenarios(), &Config::default());
    sys.setup();
    sys.write("SAFETY", None, "ENABLE", 0xf);
    sys.write("SAFETY", None, "CAUSE_MASK", 1);
    assert_eq!(sys.drive_enable(), 0xf);
    for (i, p) in plans.iter().enumerate() {
        for s in &p.segments {
            sys.push(i as u32, s);
        }
    }
    sys.write("PULSE", None, "RUN", 0xf);
    let shortest = plans.iter().map(|p| p.clocks).min().unwrap();
    sys.idle(shortest / 2);
    let moving: Vec<i32> = sys.drives.iter().map(|d| d.position).collect();
    for (i, (&p, &t)) in moving.iter().zip(&targets).enumerate() {
        assert!(p != 0 && i64::from(p) != t, "axis {i} is mid-move at {p}");
    }
    sys.estop_ok = false;
    // ESTOP_LATENCY + 2 edges to the pins (4 with QUADRATURE) and the
    // drive's own latency: after that no shaft may move.
    sys.idle(3 + 2 + 3);
    let stopped: Vec<i32> = sys.drives.iter().map(|d| d.position).collect();
    assert_eq!(sys.drive_enable(), 0, "drives disabled with HALT");
    sys.idle(20_000);
    let later: Vec<i32> = sys.drives.iter().map(|d| d.position).collect();
    assert_eq!(later, stopped, "no step after the e-stop's latency");
    assert!(
        !sys.irq(),
        "CAUSE.ESTOP unmasked: the active-low IRQ pin is low"
    );
    let status = sys.read("SAFETY", None, "STATUS");
    assert_eq!(status & 0b11, 0b11, "input asks for a stop, latch set");
    for (i, (count, position)) in sys.positions().into_iter().enumerate() {
        assert_eq!(count, later[i], "axis {i}: COUNT = shaft");
        assert_eq!(position, later[i], "axis {i}: POSITION = shaft");
        let s = sys.read("PULSE", Some(i as u32), "STATUS");
        assert_eq!(
            s & (0xffff | 1 << 17),
            0,
            "axis {i}: queue empty, no segment: {s:#x}"
        );
        assert_eq!(s >> 20 & 0x7f, 0, "axis {i}: FIFO flushed");
    }
    assert_eq!(sys.read("PULSE", None, "RUN"), 0, "RUN cleared");
    // A clear while the chain is still open does nothing; once it is
    // closed (two clocks to pass the synchroniser) it releases the latch.
    sys.write("SAFETY", None, "CLEAR", 1);
    assert_eq!(sys.read("SAFETY", None, "STATUS") & 0b10, 0b10);
    sys.estop_ok = true;
    sys.idle(3);
    sys.write("SAFETY", None, "CLEAR", 1);
    assert_eq!(sys.read("SAFETY", None, "STATUS") & 0b11, 0);
    assert_eq!(sys.drive_enable(), 0, "the drives stay off until enabled");
    sys.write("PULSE", None, "RUN", 0xf);
    sys.idle(5_000);
    let after: Vec<i32> = sys.drives.iter().map(|d| d.position).collect();
    assert_eq!(after, later, "the flushed moves do not resume");
}

/// The scenarios above run on the Verilated top ([`Engine::for_scenarios`]);
/// this one runs on both engines and must give the same trace, every pin at
/// every clock, so the rust-hdl top and its generated Verilog are one
/// controller under the whole-system stimulus too.
#[test]
fn the_system_trace_is_the_same_on_rust_hdl_and_verilator() {
    if motionhdl_testbench::harness::require_tool("verilator").is_none() {
        return;
    }
    let config = Config::default();
    let vcd = |engine| {
        let started = std::time::Instant::now();
        let text = trace_on(engine, &config).to_vcd_string();
        eprintln!("{engine:?}: {:.1} s", started.elapsed().as_secs_f64());
        text
    };
    let (rust_hdl, verilator) = (vcd(Engine::RustHdl), vcd(Engine::Verilator));
    assert!(
        rust_hdl.lines().count() > 10_000,
        "a trace of the whole move"
    );
    if let Some((k, (a, b))) = rust_hdl
        .lines()
        .zip(verilator.lines())
        .enumerate()
        .find(|(_, (a, b))| a != b)
    {
        panic!("line {}: rust-hdl `{a}`, Verilator `{b}`", k + 1);
    }
    assert_eq!(rust_hdl.lines().count(), verilator.lines().count());
}
