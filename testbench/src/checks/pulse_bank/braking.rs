//! The decelerating stop's contract (docs/pulse_generator.md, "Direction
//! stops"), over random bank traffic: from the edge a brake starts at rate
//! r (2^-32 steps/clock) with DECEL = D (2^-48 steps/clock²) to the edge
//! it ends, the NCO commands at most r² / (2^17·D) + 2 steps (v²/2a, half
//! a step for the clock-by-clock sum, one for the phase), every one of
//! them in the direction it was heading. The HDL equals the model every
//! clock under the same traffic (`pulse_bank::bank_rust`), so the model's
//! run stands for both.

use super::bank_stimulus;
use crate::harness::CheckReport;
use motionhdl_model::pulse_generator::{self as m, Request};

/// Axes and POSITION width of the bank under test.
const AXES: u32 = 4;
const WIDTH: u32 = 28;

/// One brake under way on one axis.
#[derive(Clone, Copy, Debug)]
struct Brake {
    clock: usize,
    rate: i32,
    decel: u32,
    commanded: u64,
    wrong_way: u64,
}

/// The bound on the steps a brake from `rate` at `decel` commands.
pub fn brake_steps_bound(rate: i32, decel: u32) -> u64 {
    let r = u128::from(rate.unsigned_abs());
    (r * r / (u128::from(decel) << 17)) as u64 + 2
}

/// The contract over `clocks` clocks of the bank's random traffic. Each
/// brake that ends (not cut short by HALT or reset) is a case; `scale`
/// multiplies the DECEL the bound assumes: 1 is the contract, a larger one
/// shows it able to fail. Also returns the brakes' largest share of their
/// bound, in percent.
pub fn braking_contract(clocks: usize, seed: u64, scale: u32) -> (CheckReport, u64) {
    let mut r = CheckReport::new(
        "pulse_generator",
        &format!(
            "decelerating stops in {clocks} clocks of random bank traffic: steps after the stop <= RATE^2/(2^17 DECEL) + 2"
        ),
        0,
    );
    let map = motionhdl_model::regmap::pulse_bank(AXES, WIDTH);
    let decel_addr = |i: usize| map.array("AX").address(i as u32, "DECEL");
    let mut bank = m::PulseBank::new(AXES, WIDTH);
    let mut open: Vec<Option<Brake>> = vec![None; AXES as usize];
    let mut worst = 0u64;
    for (k, v) in bank_stimulus(AXES, WIDTH, clocks, seed).iter().enumerate() {
        let before: Vec<(bool, i32, u32)> = (0..AXES as usize)
            .map(|i| {
                let decel = bank.read_value(decel_addr(i));
                (bank.engine(i).braking(), bank.nco_rate(i), decel)
            })
            .collect();
        bank.clock_stopping(v.reset, &v.bus, v.snapshot, &v.stops);
        for (i, &(was, rate, decel)) in before.iter().enumerate() {
            if v.reset || v.stops.halt {
                open[i] = None;
                continue;
            }
            let braking = bank.engine(i).braking();
            if braking && !was {
                open[i] = Some(Brake {
                    clock: k,
                    rate,
                    decel: decel.saturating_mul(scale),
                    commanded: 0,
                    wrong_way: 0,
                });
            }
            let Some(b) = open[i].as_mut() else { continue };
            match bank.generator(i).command {
                Request::None => {}
                Request::Up if b.rate > 0 => b.commanded += 1,
                Request::Down if b.rate < 0 => b.commanded += 1,
                _ => b.wrong_way += 1,
            }
            if !braking {
                let bound = brake_steps_bound(b.rate, b.decel);
                worst = worst.max(100 * b.commanded / bound);
                r.case((b.commanded > bound || b.wrong_way > 0).then(|| {
                    format!(
                        "axis {i}: brake from clock {} to {k}: {b:?}, bound {bound}",
                        b.clock
                    )
                }));
                open[i] = None;
            }
        }
    }
    // The brakes that end are counted as they come; the test asserts how
    // many.
    r.expected = r.covered;
    (r, worst)
}
