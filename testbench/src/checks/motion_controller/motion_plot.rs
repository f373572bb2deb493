//! The `system` scenario's picture: per axis, position, velocity,
//! acceleration and jerk against time, the firmware's plan beside what the
//! drives did.

use crate::plot::{self, Panel, Series};
use motionhdl_firmware::scurve::SCurveSample;
use motionhdl_firmware::ONE;

/// One axis's plan: its S-curve samples (one per tick) scaled by `scale`
/// (1 for the master, −1/2 for a follower at K = −1/2).
pub struct Plan<'a> {
    pub name: &'a str,
    pub samples: &'a [SCurveSample],
    pub scale: f64,
}

/// The plot: `plans[i]` against `executed[i]` (the drive's position at
/// each clock from the RUN write on), `tick_clocks` clocks per tick at
/// `clock_hz`; one column per axis, position, velocity, acceleration and
/// jerk down. The drives' positions are whole steps, so their velocity is
/// shown per tick and their acceleration and jerk not at all (differences
/// of whole steps per tick are quantisation noise): those are the plan's.
pub fn svg(
    banner: &str,
    plans: &[Plan],
    executed: &[Vec<i32>],
    tick_clocks: u64,
    clock_hz: u32,
) -> String {
    let tick_s = tick_clocks as f64 / f64::from(clock_hz);
    let per_s = 1.0 / tick_s;
    let ms = |tick: f64| tick * tick_s * 1e3;
    let q = |v: i64| v as f64 / ONE as f64;
    let mut columns: Vec<std::vec::IntoIter<Panel>> = Vec::new();
    for (plan, drive) in plans.iter().zip(executed) {
        let s = plan.samples;
        let planned = |f: &dyn Fn(&SCurveSample, i64) -> f64| Series {
            name: "planned".into(),
            points: s
                .iter()
                .scan(0i64, |before, x| {
                    let jerk_base = std::mem::replace(before, x.accel);
                    Some((ms(x.tick as f64), f(x, jerk_base) * plan.scale))
                })
                .collect(),
        };
        // Whole ticks recorded: clock ticks * tick_clocks is the last one
        // sampled, so it must be within the recording.
        let ticks = drive.len().saturating_sub(1) / tick_clocks as usize;
        let at_tick = |k: usize| f64::from(drive[k * tick_clocks as usize]);
        let panel = |quantity: &str, unit: &str, series: Vec<Series>| Panel {
            title: format!("{}: {quantity}", plan.name),
            x_label: "time from the RUN write (ms)".into(),
            y_label: unit.into(),
            series,
        };
        columns.push(
            vec![
                panel(
                    "position",
                    "steps",
                    vec![
                        planned(&|x, _| q(x.position)),
                        Series {
                            name: "executed (drive)".into(),
                            points: (0..=ticks).map(|k| (ms(k as f64), at_tick(k))).collect(),
                        },
                    ],
                ),
                panel(
                    "velocity",
                    "steps/s",
                    vec![
                        planned(&|x, _| q(x.velocity) * per_s),
                        Series {
                            name: "executed (steps per tick)".into(),
                            points: (1..=ticks)
                                .map(|k| (ms(k as f64), (at_tick(k) - at_tick(k - 1)) * per_s))
                                .collect(),
                        },
                    ],
                ),
                panel(
                    "acceleration (plan)",
                    "steps/s^2",
                    vec![planned(&|x, _| q(x.accel) * per_s * per_s)],
                ),
                panel(
                    "jerk (plan)",
                    "steps/s^3",
                    vec![planned(&|x, before| q(x.accel - before) * per_s.powi(3))],
                ),
            ]
            .into_iter(),
        );
    }
    let mut panels = Vec::new();
    for _ in 0..4 {
        for column in columns.iter_mut() {
            panels.extend(column.next());
        }
    }
    plot::svg(banner, plans.len(), &panels)
}
