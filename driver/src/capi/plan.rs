//! Move planning for C firmware: the firmware crate's S-curve planner
//! (`scurve_segments`), the same code the Rust tests check against the
//! move engine clock by clock.

use super::{MotionhdlSegment, MOTIONHDL_ERR_ARGUMENT, MOTIONHDL_OK};
use motionhdl_firmware::scurve_segments::{plan, EngineLimits, MAX_SEGMENTS};

/// Limits in the move engine's units (docs/pulse_generator.md): `rate`
/// in SEG_RATE LSBs (2^-32 steps/clock), `accel` in SEG_ACCEL LSBs (2^-48
/// steps/clock^2), `jerk` in SEG_JERK LSBs (2^-64 steps/clock^3).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct MotionhdlLimits {
    pub rate: i32,
    pub accel: i32,
    pub jerk: i32,
}

/// A planned move: `count` segments (at most 7, one per S-curve phase)
/// for one axis's FIFO, taking `clocks` clocks from the first load.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct MotionhdlPlan {
    pub segments: [MotionhdlSegment; MOTIONHDL_PLAN_SEGMENTS],
    pub count: u32,
    pub clocks: u64,
}

pub const MOTIONHDL_PLAN_SEGMENTS: usize = 7;
const _: () = assert!(MOTIONHDL_PLAN_SEGMENTS == MAX_SEGMENTS);

/// Limits from steps/s, steps/s^2 and steps/s^3 at `clock_hz`, rounded
/// down (out of range values are refused by `motionhdl_plan_scurve`).
#[no_mangle]
pub extern "C" fn motionhdl_limits(
    rate: f64,
    accel: f64,
    jerk: f64,
    clock_hz: f64,
) -> MotionhdlLimits {
    let l = EngineLimits::from_physical(rate, accel, jerk, clock_hz);
    MotionhdlLimits {
        rate: l.rate,
        accel: l.accel,
        jerk: l.jerk,
    }
}

/// Plans a jerk-limited move of `distance` steps (the sign is the
/// direction) from rest to rest within `*limits` into `*out`:
/// `MOTIONHDL_ERR_ARGUMENT` for a limit or distance out of range or a move
/// longer than 2^31 clocks. Stream `out->segments[0..count]` with
/// `motionhdl_stream_refill`.
///
/// # Safety
///
/// `limits` is null or valid; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_plan_scurve(
    distance: i32,
    limits: *const MotionhdlLimits,
    out: *mut MotionhdlPlan,
) -> i32 {
    // SAFETY: the caller's contract.
    let (Some(l), Some(out)) = (unsafe { limits.as_ref() }, unsafe { out.as_mut() }) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    let lim = EngineLimits {
        rate: l.rate,
        accel: l.accel,
        jerk: l.jerk,
    };
    let Ok(p) = plan(i64::from(distance), lim) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    *out = MotionhdlPlan::default();
    for (o, &s) in out.segments.iter_mut().zip(&p.segments) {
        *o = s.into();
    }
    out.count = p.segments.len() as u32;
    out.clocks = p.clocks;
    MOTIONHDL_OK
}
