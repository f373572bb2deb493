//! The standalone ×4 core against the model's channel in mode X4 with the
//! filter off: same pins, same count, every clock.

use crate::harness::{cycle, settle, CheckReport};
use motionhdl_hdl::QuadratureCore;
use motionhdl_model::counter::{Channel, ChannelInputs, CounterParams};
use rust_hdl::prelude::Block;

/// Random encoder motion (holds, forward and backward steps, illegal double
/// changes) for `cycles` clocks after a 4-clock reset. The model channel at
/// CTRL = 0 is mode X4 with both filters off; every clock compares the
/// counts and the core's look-ahead contract. One case per clock.
pub fn against_channel(width: u32, cycles: u64, seed: u64) -> CheckReport {
    let mut r = CheckReport::new(
        "quadrature_core",
        &format!("W={width}, {cycles} random clocks vs model channel (X4, F=0)"),
        cycles,
    );
    let mut core = QuadratureCore::new(width);
    core.connect_all();
    let mut model = Channel::new(CounterParams::new(width, 8));
    let mut x = seed | 1;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let gray = [(false, false), (true, false), (true, true), (false, true)];
    let mut phase = 0usize;
    let clock = |core: &mut QuadratureCore, model: &mut Channel, a, b, reset| {
        core.a.next = a;
        core.b.next = b;
        core.reset.next = reset;
        settle(core);
        cycle(core, |c| &mut c.clock);
        model.clock(&ChannelInputs {
            a,
            b,
            reset,
            ..Default::default()
        });
    };
    for _ in 0..4 {
        clock(&mut core, &mut model, false, false, true);
    }
    for n in 0..cycles {
        let roll = next() % 100;
        let (a, b) = match roll {
            0..=39 => gray[phase],
            40..=69 => {
                phase = (phase + 1) % 4;
                gray[phase]
            }
            70..=94 => {
                phase = (phase + 3) % 4;
                gray[phase]
            }
            _ => {
                phase = (phase + 2) % 4; // both change: illegal, not counted
                gray[phase]
            }
        };
        clock(&mut core, &mut model, a, b, false);
        let (got, want) = (core.value(), model.state().count);
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

/// The core checks `motionhdl verify` runs.
pub fn all() -> Vec<CheckReport> {
    vec![
        against_channel(4, 100_000, 0x9e37_79b9),
        against_channel(32, 100_000, 0x2545_f491),
    ]
}

#[cfg(test)]
mod tests {
    #[test]
    fn core_counts_like_a_channel_in_x4() {
        for r in super::all() {
            r.assert_passed();
        }
    }
}
