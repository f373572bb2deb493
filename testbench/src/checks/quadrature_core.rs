//! The standalone ×4 core against the model's channel in mode X4 with the
//! filter off: same pins, same count, every clock; in rust-hdl and as the
//! generated Verilog in Icarus and Verilator.

use crate::harness::{cycle, settle, CheckReport, Rng};
use crate::verilog_sim::{ports_of, run_vectors, Design, Simulator, Target};
use motionhdl_hdl::{catalog, QuadratureCore};
use motionhdl_model::counter::{Channel, ChannelInputs, CounterParams};
use rust_hdl::prelude::Block;

/// One clock of stimulus: pins A, B and reset.
type Pins = (bool, bool, bool);

/// A 4-clock reset, then random encoder motion (holds, forward and
/// backward steps, illegal double changes) for `cycles` clocks.
fn stimulus(cycles: u64, seed: u64) -> Vec<Pins> {
    let mut next = Rng::stream(seed);
    let gray = [(false, false), (true, false), (true, true), (false, true)];
    let mut phase = 0usize;
    let mut v = vec![(false, false, true); 4];
    for _ in 0..cycles {
        phase = match next() % 100 {
            0..=39 => phase,
            40..=69 => (phase + 1) % 4,
            70..=94 => (phase + 3) % 4,
            _ => (phase + 2) % 4, // both change: illegal, not counted
        };
        let (a, b) = gray[phase];
        v.push((a, b, false));
    }
    v
}

/// The model channel (CTRL = 0: mode X4, filters off) through `pins`: the
/// count after every clock.
fn model_counts(width: u32, pins: &[Pins]) -> Vec<u32> {
    let mut model = Channel::new(CounterParams::new(width, 8));
    pins.iter()
        .map(|&(a, b, reset)| {
            model.clock(&ChannelInputs {
                a,
                b,
                reset,
                ..Default::default()
            });
            model.state().count
        })
        .collect()
}

/// The rust-hdl core against the model channel, every clock, with the
/// core's look-ahead contract. One case per clock after reset.
pub fn against_channel(width: u32, cycles: u64, seed: u64) -> CheckReport {
    let mut r = CheckReport::new(
        "quadrature_core",
        &format!("W={width}, {cycles} random clocks vs model channel (X4, F=0)"),
        cycles,
    );
    let pins = stimulus(cycles, seed);
    let want = model_counts(width, &pins);
    let mut core = QuadratureCore::new(width);
    core.connect_all();
    for (n, (&(a, b, reset), &want)) in pins.iter().zip(&want).enumerate() {
        core.a.next = a;
        core.b.next = b;
        core.reset.next = reset;
        settle(&mut core);
        cycle(&mut core, |c| &mut c.clock);
        if reset {
            continue;
        }
        let got = core.value();
        r.case(if got != want {
            Some(format!(
                "clock {n} pins ({a},{b}): core {got:#x}, model {want:#x}"
            ))
        } else if !core.lookahead_consistent() {
            Some(format!(
                "clock {n}: look-ahead flags do not match the low half"
            ))
        } else {
            None
        });
        if !r.failures.is_empty() {
            break;
        }
    }
    r
}

/// The same stimulus through the generated `quadrature_core.v` (or its
/// netlist): the `count` port after every clock against the model channel.
pub fn verilog_against_channel(
    target: impl Into<Target>,
    width: u32,
    cycles: u64,
    seed: u64,
) -> CheckReport {
    let t = target.into();
    let mut r = CheckReport::new(
        "quadrature_core",
        &format!(
            "W={width}, {cycles} random clocks, {} vs model channel",
            t.describe()
        ),
        cycles,
    );
    let pins = stimulus(cycles, seed);
    let want = model_counts(width, &pins);
    let m = catalog::quadrature_core(width);
    let text = match t.text(&m) {
        Ok(text) => text,
        Err(e) if t.available().is_err() => return r.skip(e),
        Err(e) => {
            r.failures.push(e);
            return r;
        }
    };
    let design = Design {
        top: m.name,
        source: &text,
        inputs: ports_of(&m, &["a", "b", "reset"]),
        outputs: ports_of(&m, &["count"]),
        clock: Some("clock"),
    };
    // The testbench prints outputs before each edge: row n + 1 is the count
    // after clock n. One trailing idle vector shows the last count.
    let mut vectors: Vec<Vec<u64>> = pins
        .iter()
        .map(|&(a, b, reset)| vec![u64::from(a), u64::from(b), u64::from(reset)])
        .collect();
    vectors.push(vec![0, 0, 0]);
    match run_vectors(t.sim, &design, &vectors) {
        Ok(rows) => {
            for (n, (&(_, _, reset), &want)) in pins.iter().zip(&want).enumerate() {
                if reset {
                    continue;
                }
                let got = rows[n + 1][0];
                r.case(
                    (got != u64::from(want))
                        .then(|| format!("clock {n}: Verilog count {got:#x}, model {want:#x}")),
                );
            }
        }
        Err(e) if t.available().is_err() => return r.skip(e),
        Err(e) => r.failures.push(e),
    }
    r
}

/// The core checks `motionhdl verify` runs; the generated Verilog in Icarus
/// and Verilator only when `external` is set.
pub fn all(external: bool) -> Vec<CheckReport> {
    let runs = [(4, 0x9e37_79b9), (32, 0x2545_f491)];
    let mut v: Vec<CheckReport> = runs
        .iter()
        .map(|&(w, seed)| against_channel(w, 100_000, seed))
        .collect();
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            for &(w, seed) in &runs {
                v.push(verilog_against_channel(sim, w, 100_000, seed));
            }
        }
    }
    v
}

#[cfg(test)]
mod tests {
    #[test]
    fn core_counts_like_a_channel_in_x4() {
        // rust-hdl, Icarus and Verilator (a missing simulator fails in CI).
        for r in super::all(true) {
            r.assert_passed();
        }
    }
}
