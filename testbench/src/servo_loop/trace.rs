//! `motionhdl trace servo_loop`: the circle of tests/servo_loop.rs as a
//! trace, one sample per servo tick (the fine setpoint, the tick's count,
//! the error, the staged code, the DAC's output voltage and the slide's
//! speed per axis, as analog curves), and a plot of commanded versus
//! measured position and the DAC outputs.
//!
//! The one scenario not stepped on the rust-hdl blocks: the run is 3.1 M
//! clocks (the rust-hdl top runs about 5.8 k clocks/s, 9 minutes), so it
//! runs on the servo card top's model, which `tests/top_model.rs` holds to
//! the rust-hdl top pin for pin every clock and `tests/servo_loop.rs`
//! shows giving the same tick log as the rust-hdl top over 12 periods.

use super::dsp::{self, Tick, TICK_CLOCKS};
use super::{card_with, circle, plant, AXES, CLOCK_S};
use crate::plot::{self, Panel, Series};
use crate::trace::Trace;
use motionhdl_model::servo_dac::SAFE_CODE;

/// Coarse points (one turn of 24) and fine points per span: a turn in 960
/// ticks (48 ms); then 200 ticks holding the end point.
const COARSE_POINTS: u32 = 24;
const FINE_PER_SPAN: u32 = 40;
const HOLD_TICKS: usize = 200;

/// The run's tick log.
pub fn run() -> Vec<Tick> {
    let (mut card, fine) = card_with(&circle(COARSE_POINTS), FINE_PER_SPAN);
    dsp::run(&mut card, &fine, fine.len() + HOLD_TICKS, |_, _| {})
}

/// The trace of [`run`] with its plot attached.
pub fn trace() -> Trace {
    trace_of(&run())
}

/// The trace of a tick log with its plot attached.
pub fn trace_of(log: &[Tick]) -> Trace {
    let mut t = Trace::new(format!(
        "{} | scenario servo_loop | servo card model, 50 MHz | tick every {TICK_CLOCKS} clocks \
         | a circle of r = 500 counts, {COARSE_POINTS} coarse points, {FINE_PER_SPAN} fine per span",
        motionhdl_hdl::banner_ascii()
    ));
    let ids: Vec<[_; 6]> = ["x", "y"]
        .iter()
        .map(|axis| {
            let scope = ["servo_loop", axis];
            [
                t.analog(&scope, "setpoint_counts", 32),
                t.analog(&scope, "count", 32),
                t.analog(&scope, "error_counts", 32),
                t.analog_unsigned(&scope, "code", 16),
                t.analog(&scope, "dac_mv", 16),
                t.analog(&scope, "speed_um_per_s", 32),
            ]
        })
        .collect();
    // At rest before the first tick: nothing commanded, 0 V.
    let rest = Tick {
        dac: [SAFE_CODE as u16; AXES],
        code: [SAFE_CODE as u16; AXES],
        ..Default::default()
    };
    let ns_per_clock = (CLOCK_S * 1e9).round() as u64;
    for k in std::iter::once(&rest).chain(log) {
        for (i, id) in ids.iter().enumerate() {
            let setpoint = k.setpoint[i].round() as i64;
            let values: [i64; 6] = [
                setpoint,
                i64::from(k.count[i]),
                setpoint - i64::from(k.count[i]),
                i64::from(k.code[i]),
                (plant::code_volts(k.dac[i]) * 1000.0).round() as i64,
                (k.velocity[i] * 1e6).round() as i64,
            ];
            for (id, v) in id.iter().zip(values) {
                t.set_quantity(k.clock * ns_per_clock, *id, v);
            }
        }
    }
    if let Some(first) = log.first() {
        t.mark(first.clock * ns_per_clock, "first tick");
    }
    if let Some(hold) = log.len().checked_sub(HOLD_TICKS + 1).map(|i| &log[i]) {
        t.mark(hold.clock * ns_per_clock, "last fine point: holding");
    }
    t.set_plot(picture(&motionhdl_hdl::banner(), log));
    t
}

/// Commanded versus measured position per axis against time, the DAC
/// outputs, and the path in the plane.
fn picture(banner: &str, log: &[Tick]) -> String {
    let ms = |k: &Tick| k.clock as f64 * CLOCK_S * 1e3;
    let curve = |name: &str, f: &dyn Fn(&Tick) -> f64| Series {
        name: name.into(),
        points: log.iter().map(|k| (ms(k), f(k))).collect(),
    };
    let mut panels: Vec<Panel> = ["X", "Y"]
        .iter()
        .enumerate()
        .map(|(i, axis)| Panel {
            title: format!("{axis}: commanded and measured"),
            x_label: "time (ms)".into(),
            y_label: "position (counts = um)".into(),
            series: vec![
                curve("fine setpoint", &|k| k.setpoint[i]),
                curve("COUNT at the tick", &|k| f64::from(k.count[i])),
            ],
        })
        .collect();
    panels.push(Panel {
        title: "DAC outputs".into(),
        x_label: "time (ms)".into(),
        y_label: "volts".into(),
        series: (0..AXES)
            .map(|i| curve(["X (A)", "Y (B)"][i], &|k| plant::code_volts(k.dac[i])))
            .collect(),
    });
    let path = |name: &str, f: &dyn Fn(&Tick) -> (f64, f64)| Series {
        name: name.into(),
        points: log.iter().map(f).collect(),
    };
    panels.push(Panel {
        title: "the path".into(),
        x_label: "X (counts)".into(),
        y_label: "Y (counts)".into(),
        series: vec![
            path("commanded", &|k| (k.setpoint[0], k.setpoint[1])),
            path("measured", &|k| {
                (f64::from(k.count[0]), f64::from(k.count[1]))
            }),
        ],
    });
    plot::svg(banner, 2, &panels)
}
