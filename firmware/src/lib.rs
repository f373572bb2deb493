//! Motion algorithms of the three seed controllers: the firmware half that
//! runs on the MCU/DSP and feeds the FPGA. `no_std`; the `alloc` feature
//! (on by default) adds the helpers that return a `Vec`.
//!
//! | module | seed | what |
//! |---|---|---|
//! | [`trapezoid`] | dual-CPU STM32 card | point counts of the accel/cruise/decel phases the master computes before a move; a per-tick stepper |
//! | [`scurve`] | STM32 + FPGA card | 7-segment jerk-limited S-curve whose deceleration point is found by comparing the remaining distance with the braking distance every tick (steps 1-5) |
//! | [`bspline`] | TMS320C32 DSP card | cubic uniform B-spline fine interpolation of coarse points |
//! | [`pid`] | TMS320C32 DSP card | incremental PID to a 16-bit DAC |
//! | [`homing`] | STM32 + FPGA card | home search against the HOME switch the gateware captures: fast search, back-off, slow search, optional index, non-blocking |
//! | [`frames`] | dual-CPU STM32 card | master/slave "virtual memory" frames with CRC-16/MODBUS |
//! | [`segments`] | (this project) | a sampled profile as segments for the FPGA pulse generator's move FIFO |
//! | [`scurve_segments`] | STM32 + FPGA card | the 7-phase S-curve as at most 7 segments with a jerk, one per phase |
//!
//! The algorithms use `core` only and no heap; where a `Vec` of output is
//! the natural result, a separate `*_vec`-style helper builds it.
//!
//! # Fixed point
//!
//! Profiles run on a servo tick. Positions, velocities, accelerations and
//! jerks are Q32.32 numbers in an `i64`: the value times 2^32, in steps,
//! steps/tick, steps/tick² and steps/tick³ ([`ONE`] is one step). A
//! velocity of `v` is the distance covered in one tick, so a profile is an
//! exact integer sum and never drifts. The whole steps a position stands for
//! are its floor ([`whole_steps`]). The PID uses Q16.16 gains
//! ([`pid`]); the B-spline is `f64`, as the TMS320C32 was a floating-point
//! DSP.

#![no_std]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod bspline;
pub mod frames;
pub mod homing;
pub mod pid;
pub mod scurve;
pub mod scurve_segments;
pub mod segments;
pub mod trapezoid;

use core::fmt;

/// Fractional bits of the Q32.32 profile quantities.
pub const FRAC_BITS: u32 = 32;
/// One step (or one step/tick, ...) in Q32.32.
pub const ONE: i64 = 1 << FRAC_BITS;

/// The whole steps of a Q32.32 position: its floor, so that a profile's
/// per-tick step counts telescope to the whole-step distance.
pub fn whole_steps(q: i64) -> i64 {
    q >> FRAC_BITS
}

/// A parameter outside the range an algorithm accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutOfRange {
    /// The parameter's name as in the params struct.
    pub name: &'static str,
    pub value: i64,
    pub min: i64,
    pub max: i64,
}

impl OutOfRange {
    /// `Ok(value)` when `min <= value <= max`, else the error naming it.
    pub fn check(name: &'static str, value: i64, min: i64, max: i64) -> Result<i64, Self> {
        if (min..=max).contains(&value) {
            Ok(value)
        } else {
            Err(Self {
                name,
                value,
                min,
                max,
            })
        }
    }
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} = {} out of range {}..={}",
            self.name, self.value, self.min, self.max
        )
    }
}

impl core::error::Error for OutOfRange {}
