//! The servo card's loop closed in simulation (docs/servo_loop.md): PC →
//! ISA → shared RAM → DSP firmware (B-spline, PID) → DAC → motors → rulers
//! → counters, on the bit-accurate model of the servo card's top. The
//! bounds are the measured figures with a margin (docs/servo_loop.md).

use motionhdl_model::servo_dac::{serial_update_latency, update_latency, SAFE_CODE};
use motionhdl_testbench::servo_loop::dsp::{self, Tick};
use motionhdl_testbench::servo_loop::{card_with, circle, plant, serial_card_with, ServoCard};

/// The largest |setpoint − count| of `axis` over `log`.
fn following_error(log: &[Tick], axis: usize) -> f64 {
    log.iter()
        .map(|t| (t.setpoint[axis] - f64::from(t.count[axis])).abs())
        .fold(0.0, f64::max)
}

/// The first tick from which `axis` stays within ±`band` counts of `target`.
fn settled_from(log: &[Tick], axis: usize, target: i32, band: i32) -> Option<usize> {
    let last_out = log
        .iter()
        .rposition(|t| (t.count[axis] - target).abs() > band);
    match last_out {
        Some(k) if k + 1 == log.len() => None,
        Some(k) => Some(k + 1),
        None => Some(0),
    }
}

/// Opens the e-stop chain and idles until the motors' DAC outputs all
/// read 0 V, at most `limit` clocks: the clocks it took.
fn estop_to_0_v(card: &mut ServoCard, limit: u64) -> u64 {
    card.estop_ok = false;
    let start = card.clocks;
    while card.dac_output() != [SAFE_CODE as u16; 4] && card.clocks < start + limit {
        card.idle(1);
    }
    card.clocks - start
}

#[test]
fn a_1_mm_move_settles_without_overshoot() {
    let (mut card, fine) = card_with(&[[0, 0], [1000, 0]], 100);
    assert_eq!(fine.len(), 301, "3 spans of 100 fine points, and the end");
    let log = dsp::run(&mut card, &fine, 1200, |_, _| {});
    let max = log.iter().map(|t| t.count[0]).max().unwrap();
    let settled = settled_from(&log, 0, 1000, 2).expect("settles to ±2 counts");
    eprintln!(
        "1 mm move: max {max} counts, settled (±2) from tick {settled}, lag {:.1}",
        following_error(&log, 0)
    );
    assert!(max <= 1010, "overshoot {} counts (bound 10)", max - 1000);
    assert!(
        settled <= 800,
        "settled from tick {settled} (bound 800 = 40 ms)"
    );
    assert!(log.iter().all(|t| t.count[1].abs() <= 1), "Y stood still");
}

#[test]
fn a_circle_from_the_pc_is_followed_within_the_stated_error() {
    // 24 coarse points per turn, radius 500 counts (0.5 mm), 1.5 turns; 40
    // fine points per span: a turn every 960 ticks (48 ms, 65 mm/s).
    let coarse = circle(36);
    let (mut card, fine) = card_with(&coarse, 40);
    let log = dsp::run(&mut card, &fine, fine.len() + 200, |_, _| {});
    // From the first full span on (the start from rest is the step case).
    let on_circle = &log[80..fine.len()];
    let (ex, ey) = (following_error(on_circle, 0), following_error(on_circle, 1));
    eprintln!("circle: following error X {ex:.1}, Y {ey:.1} counts");
    assert!(
        ex <= 30.0 && ey <= 30.0,
        "following error {ex:.1} / {ey:.1} (bound 30)"
    );
    let end = log.last().unwrap();
    for i in 0..2 {
        assert!(
            (end.setpoint[i] - f64::from(end.count[i])).abs() <= 2.0,
            "{end:?}"
        );
    }
}

#[test]
fn a_saturating_move_does_not_wind_up() {
    // 5 mm in 3 spans of 40 ticks (6 ms): the error the profile's start
    // and stop leave, with Kp 80 and τd 8 ms, asks for more than ±10 V,
    // so the DAC sits at full scale, both ways. The velocity-form PID
    // keeps u(k−1) clamped: nothing accumulates beyond the DAC's range,
    // so the slide comes in without a wound-up overshoot.
    let (mut card, fine) = card_with(&[[0, 0], [5_000, 0]], 40);
    let log = dsp::run(&mut card, &fine, 2500, |_, _| {});
    let high = log.iter().filter(|t| t.dac[0] == 0xFFFF).count();
    let low = log.iter().filter(|t| t.dac[0] == 0).count();
    let max = log.iter().map(|t| t.count[0]).max().unwrap();
    eprintln!(
        "5 mm move: {high} ticks at +full scale, {low} at -full scale, max {max}, \
         count at ticks 500/1500/2500: {} / {} / {}",
        log[500].count[0], log[1500].count[0], log[2499].count[0]
    );
    assert!(high + low >= 10, "{high} + {low} ticks at full scale");
    assert!(
        max - 5_000 <= 10,
        "overshoot {} counts (bound 10)",
        max - 5_000
    );
    // After the saturation the slide creeps in from below, never past:
    // the velocity form's price (what the clamp dropped is not made up).
    let creep = &log[500..];
    assert!(creep.windows(2).all(|w| w[1].count[0] >= w[0].count[0] - 1));
    assert!(log[2499].count[0] > log[1500].count[0] && log[2499].count[0] < 5_000);
}

#[test]
fn an_estop_drives_the_dac_to_0_v_and_the_slides_coast_to_rest() {
    let coarse = circle(24);
    let (mut card, fine) = card_with(&coarse, 40);
    let mut latency = None;
    let log = dsp::run(&mut card, &fine, 2400, |k, card| {
        if k == 400 {
            latency = Some(estop_to_0_v(card, 1000));
        }
    });
    let latency = latency.unwrap();
    // The chain's two-flop synchroniser, the latch, HALT; a transfer that
    // may be running, then the safe one.
    let bound = u64::from(2 * update_latency(2, 2) + 6);
    eprintln!("e-stop to 0 V on all four outputs: {latency} clocks (bound {bound})");
    assert!(latency <= bound, "{latency} clocks");
    let after = &log[401..];
    assert!(
        after.iter().all(|t| t.dac == [SAFE_CODE as u16; 2]),
        "0 V from then on"
    );
    // Coasting: the speed only falls (friction, no force), to rest.
    for w in after.windows(2) {
        for i in 0..2 {
            assert!(
                w[1].velocity[i].abs() <= w[0].velocity[i].abs() + 1e-12,
                "{w:?}"
            );
        }
    }
    // 100 ms = 10 time constants (m/b = 10 ms) after the e-stop: at rest,
    // having coasted v·m/b from where the DAC went to 0 V.
    let end = log.last().unwrap();
    let moved = (0..2).map(|i| (end.count[i] - log[log.len() - 200].count[i]).abs());
    assert!(
        moved.max().unwrap() == 0,
        "still moving at the end: {end:?}"
    );
    assert!(end.velocity.iter().all(|v| v.abs() < 1e-5), "{end:?}");
    let at = &log[401];
    assert!(
        at.velocity.iter().any(|v| v.abs() > 0.01),
        "was moving: {at:?}"
    );
    for i in 0..2 {
        let coast =
            at.velocity[i] * plant::MASS_KG / plant::FRICTION_N_S_PER_M / plant::RULER_M_PER_COUNT;
        let got = end.position[i] - at.position[i];
        eprintln!("axis {i}: coasted {got:.2} counts, v·m/b = {coast:.2}");
        assert!((got - coast).abs() <= 1.0, "axis {i}: {got} vs {coast}");
    }
}

#[test]
fn the_loop_runs_the_same_on_the_rust_hdl_top() {
    // The setup, the PC's points, the doorbell and 12 servo periods of the
    // 1 mm move, on the rust-hdl top and on the model: the same clocks,
    // counts, codes, DAC outputs and slide positions at every tick.
    let run = |mut card: ServoCard| {
        dsp::setup(&mut card);
        card.pc_send(&dsp::encode_points(&[[0, 0], [1000, 0]]));
        let fine = dsp::fine_setpoints(&dsp::receive_points(&mut card), 4);
        let log = dsp::run(&mut card, &fine, 12, |_, _| {});
        (log, card.clocks)
    };
    let t0 = std::time::Instant::now();
    let (hdl, hdl_clocks) = run(ServoCard::on_rust_hdl());
    eprintln!("rust-hdl: {hdl_clocks} clocks in {:?}", t0.elapsed());
    let (model, model_clocks) = run(ServoCard::new());
    assert_eq!(hdl_clocks, model_clocks);
    assert!(hdl_clocks > 30_000, "{hdl_clocks} clocks");
    for (k, (h, m)) in hdl.iter().zip(&model).enumerate() {
        assert_eq!(h, m, "tick {k}");
    }
    assert!(
        model.last().unwrap().count[0] > 0,
        "it moved: {:?}",
        model.last()
    );
}

#[test]
fn a_hung_dsp_is_bitten_by_the_watchdog_and_the_dac_goes_to_0_v() {
    use motionhdl_model::safety_io::WATCHDOG_KEY;
    // The firmware reloads the watchdog every period; at period 300 it
    // hangs for 20 000 clocks (8 periods): the watchdog (3 periods) bites,
    // HALT sends the safe code, and the slides coast although the firmware
    // runs again afterwards (the bite holds until SAFETY.CLEAR).
    const TIMEOUT: u32 = 3 * dsp::TICK_CLOCKS;
    let (mut card, fine) = card_with(&circle(24), 40);
    card.write("SAFETY", None, "WDT_TIMEOUT", TIMEOUT);
    let mut last_reload = 0;
    let mut safe_after = None;
    let log = dsp::run(&mut card, &fine, 2700, |k, card| {
        if k < 300 {
            card.write("SAFETY", None, "WDT_RELOAD", WATCHDOG_KEY);
            last_reload = card.clocks;
        } else if k == 300 {
            let start = card.clocks;
            while card.clocks < start + 20_000 {
                card.idle(1);
                if safe_after.is_none() && card.dac.output == [SAFE_CODE as u16; 4] {
                    safe_after = Some(card.clocks - last_reload);
                }
            }
        }
    });
    let safe_after = safe_after.expect("the DAC went to 0 V while the DSP hung");
    let bound = u64::from(TIMEOUT + 2 * update_latency(2, 2) + 6);
    eprintln!(
        "watchdog: 0 V on all outputs {safe_after} clocks after the last reload (bound {bound})"
    );
    assert!(
        safe_after > u64::from(TIMEOUT),
        "{safe_after}: not before the timeout"
    );
    assert!(safe_after <= bound, "{safe_after} clocks");
    assert!(log[301..].iter().all(|t| t.dac == [SAFE_CODE as u16; 2]));
    assert!(
        log[299].velocity.iter().any(|v| v.abs() > 0.01),
        "was moving"
    );
    let end = log.last().unwrap();
    assert!(
        end.velocity.iter().all(|v| v.abs() < 1e-5),
        "coasted to rest: {end:?}"
    );
}

#[test]
fn the_trace_shows_the_circle_run_per_tick_with_its_plot() {
    use motionhdl_testbench::servo_loop::trace;
    let log = trace::run();
    let t = trace::trace_of(&log);
    let vcd = t.to_vcd_string();
    // Values from time 0, at rest; then one sample per tick (20 ns a
    // clock), the last one the run's last tick.
    let body = &vcd[vcd.find("$enddefinitions").unwrap()..];
    assert!(body.contains("\n#0\n"), "no values at time 0");
    let last = log.last().unwrap();
    assert!(
        vcd.contains(&format!("\n#{}\n", last.clock * 20)),
        "last tick's sample"
    );
    let gtkw = t.to_gtkw("servo_loop.vcd");
    assert_eq!(gtkw.matches("@8424\n").count(), 10, "signed analog curves");
    assert_eq!(gtkw.matches("@8024\n").count(), 2, "the codes, unsigned");
    let svg = t.plot().expect("a plot");
    // 4 panels of 2 curves, each with its legend swatch.
    assert_eq!(motionhdl_testbench::plot::curves(svg), 16);
    // The DAC chatter the plot shows (docs/servo_loop.md, "Trace"): the
    // derivative term on a one-count error step is Kp·τd/T codes.
    let kick = dsp::KP * dsp::TAU_D_S / (f64::from(dsp::TICK_CLOCKS) * 20e-9);
    let steps: Vec<i32> = log
        .windows(2)
        .map(|w| (i32::from(w[1].code[0]) - i32::from(w[0].code[0])).abs())
        .collect();
    let big = steps.iter().filter(|&&d| f64::from(d) > kick / 2.0).count();
    eprintln!(
        "servo_loop trace: {} ticks; X code steps over Kp*td/T/2 = {:.0}: {big}; largest {}",
        log.len(),
        kick / 2.0,
        steps.iter().max().unwrap()
    );
    assert!(big > 0, "the derivative kick is in the run");
}

#[test]
fn the_loop_closes_the_same_through_the_serial_dac() {
    // The 1 mm move with the motors on the SPI DAC (AD5686R-style, reset
    // SERIAL times: the update 209 clocks after the tick instead of 23).
    let (mut card, fine) = serial_card_with(&[[0, 0], [1000, 0]], 100);
    let log = dsp::run(&mut card, &fine, 1200, |_, _| {});
    let max = log.iter().map(|t| t.count[0]).max().unwrap();
    let settled = settled_from(&log, 0, 1000, 2).expect("settles to ±2 counts");
    eprintln!(
        "1 mm move on the serial DAC: max {max} counts, settled (±2) from tick {settled}, \
         {} frames",
        card.spi_dac.frames
    );
    assert!(max <= 1010, "overshoot {} counts (bound 10)", max - 1000);
    assert!(settled <= 800, "settled from tick {settled} (bound 800)");
    assert!(card.spi_dac.frames >= 4 * 1199, "{:?}", card.spi_dac);
    assert_eq!(card.spi_dac.bad_frames, 0, "{:?}", card.spi_dac);
    // The parallel pins wrote nothing after the mode switch.
    assert_eq!(card.dac.output, [SAFE_CODE as u16; 4]);
    // An e-stop while moving: 0 V on all four serial outputs in bounded
    // time, and from then on.
    let (mut card, fine) = serial_card_with(&circle(24), 40);
    let mut latency = None;
    let log = dsp::run(&mut card, &fine, 600, |k, card| {
        if k == 400 {
            latency = Some(estop_to_0_v(card, 2000));
        }
    });
    let latency = latency.unwrap();
    let bound = u64::from(2 * serial_update_latency(0, 1, 2) + 6);
    eprintln!("e-stop to 0 V on the serial DAC: {latency} clocks (bound {bound})");
    assert!(latency <= bound, "{latency} clocks");
    assert!(log[401..].iter().all(|t| t.dac == [SAFE_CODE as u16; 2]));
    assert!(log[399].dac != [SAFE_CODE as u16; 2], "was driving");
}
