//! Trapezoidal moves of the dual-CPU STM32 card (seed 000, section 2): the
//! user sets the initial speed, acceleration, target speed, deceleration and
//! the target point (step) count; the master computes before the move how
//! many points each phase runs ([`plan`]). [`TrapezoidStepper`] samples the
//! move on a servo tick.
//!
//! Units: speeds in steps/s (the pulse frequency), accelerations in
//! steps/s², counts in steps. The initial speed is also the stop speed: a
//! stepper starts at it from rest and stops from it, as the card's pulse
//! output does. The direction is not part of the profile (the seed drives
//! S2 separately); counts are magnitudes.

use crate::{OutOfRange, FRAC_BITS, ONE};

/// Highest target speed: half a 50 MHz pulse-generator clock.
pub const MAX_SPEED: u32 = 25_000_000;
/// Highest acceleration and deceleration, steps/s².
pub const MAX_ACCEL: u32 = 1_000_000_000;
/// Highest point count: the pulse generator's position is a signed 32-bit
/// count.
pub const MAX_STEPS: u32 = i32::MAX as u32;
/// Highest servo tick rate of [`TrapezoidStepper`].
pub const MAX_TICK_HZ: u32 = 1_000_000;

/// What the user sets for one move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TrapezoidParams {
    /// Initial (and final) speed, steps/s: 0..=target_speed.
    pub start_speed: u32,
    /// Acceleration, steps/s²: 1..=[`MAX_ACCEL`].
    pub accel: u32,
    /// Target (cruise) speed, steps/s: 1..=[`MAX_SPEED`].
    pub target_speed: u32,
    /// Deceleration, steps/s²: 1..=[`MAX_ACCEL`].
    pub decel: u32,
    /// Target point count: 0..=[`MAX_STEPS`].
    pub steps: u32,
}

impl TrapezoidParams {
    /// Every parameter in its range, else the first bad one.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        let target = OutOfRange::check(
            "target_speed",
            self.target_speed.into(),
            1,
            MAX_SPEED.into(),
        )?;
        OutOfRange::check("start_speed", self.start_speed.into(), 0, target)?;
        OutOfRange::check("accel", self.accel.into(), 1, MAX_ACCEL.into())?;
        OutOfRange::check("decel", self.decel.into(), 1, MAX_ACCEL.into())?;
        OutOfRange::check("steps", self.steps.into(), 0, MAX_STEPS.into())?;
        Ok(())
    }
}

/// The master's point counts: `accel_steps + cruise_steps + decel_steps`
/// is the target count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TrapezoidPlan {
    pub accel_steps: u32,
    pub cruise_steps: u32,
    pub decel_steps: u32,
    /// Highest speed reached, steps/s (the target speed unless triangular).
    pub peak_speed: u32,
    /// The move is too short to reach the target speed.
    pub triangular: bool,
}

/// Point counts of each phase, in integer arithmetic as the master would:
/// accelerating from v0 to vt at a takes (vt² − v0²)/(2a) points (floor),
/// decelerating back to v0 at d takes (vt² − v0²)/(2d). When both exceed
/// the target count N, the move is triangular: the accel and decel ramps
/// meet where v0² + 2a·n_acc = v0² + 2d·n_dec, i.e. n_acc = N·d/(a + d)
/// (floor), and the peak is √(v0² + 2a·n_acc).
pub fn plan(p: &TrapezoidParams) -> Result<TrapezoidPlan, OutOfRange> {
    p.validate()?;
    let (v0, vt) = (u64::from(p.start_speed), u64::from(p.target_speed));
    let (a, d, n) = (u64::from(p.accel), u64::from(p.decel), u64::from(p.steps));
    // vt <= 2.5e7, so vt² fits easily in u64.
    let dv2 = vt * vt - v0 * v0;
    let acc_full = dv2 / (2 * a);
    let dec_full = dv2 / (2 * d);
    let plan = if acc_full + dec_full <= n {
        TrapezoidPlan {
            accel_steps: acc_full as u32,
            cruise_steps: (n - acc_full - dec_full) as u32,
            decel_steps: dec_full as u32,
            peak_speed: p.target_speed,
            triangular: false,
        }
    } else {
        let acc = (u128::from(n) * u128::from(d) / u128::from(a + d)) as u64;
        let peak = (u128::from(v0 * v0) + 2 * u128::from(a) * u128::from(acc)).isqrt() as u64;
        TrapezoidPlan {
            accel_steps: acc as u32,
            cruise_steps: 0,
            decel_steps: (n - acc) as u32,
            peak_speed: peak.min(vt) as u32,
            triangular: true,
        }
    };
    Ok(plan)
}

/// The stepper's limits per servo tick, Q32.32 (see [`super`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TickLimits {
    /// Start/stop speed, steps/tick.
    pub start: i64,
    /// Velocity increase per tick.
    pub accel: i64,
    /// Cruise speed, steps/tick.
    pub max: i64,
    /// Velocity decrease per tick.
    pub decel: i64,
}

impl TickLimits {
    /// Converts steps/s and steps/s² at `tick_hz`, rounding to nearest; the
    /// accelerations are at least one LSB so that a move always progresses.
    pub fn new(p: &TrapezoidParams, tick_hz: u32) -> Self {
        let t = u128::from(tick_hz);
        let per = |x: u32, den: u128| ((u128::from(x) << FRAC_BITS) + den / 2) / den;
        Self {
            start: per(p.start_speed, t) as i64,
            accel: (per(p.accel, t * t) as i64).max(1),
            max: per(p.target_speed, t) as i64,
            decel: (per(p.decel, t * t) as i64).max(1),
        }
    }

    /// Speed from which a stop (to 0 in one tick) is allowed: the start
    /// speed, or one tick of deceleration if that is more.
    pub fn stop(&self) -> i64 {
        self.start.max(self.decel)
    }
}

/// Phase of one stepper tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TrapezoidPhase {
    /// Standing (the first sample and the last).
    #[default]
    Rest,
    Accel,
    Cruise,
    Decel,
}

/// One tick of a trapezoidal move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TrapezoidSample {
    pub tick: u64,
    /// Q32.32 steps; its floor is the commanded whole-step count.
    pub position: i64,
    /// Distance covered in the tick ending here, Q32.32 steps/tick.
    pub velocity: i64,
    pub phase: TrapezoidPhase,
}

/// Samples a trapezoidal move per servo tick. Each tick the next velocity is
/// the largest one, within the acceleration and the target speed, from which
/// the remaining distance can still be covered at the deceleration limit: so
/// the deceleration point is where the remaining distance meets the braking
/// distance, and the move lands exactly on the target count (the last tick
/// covers whatever is left, at most the stop speed).
///
/// Yields tick 0 at rest, then one sample per tick up to and including the
/// first at rest on the target.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TrapezoidStepper {
    lim: TickLimits,
    target: i64,
    position: i64,
    velocity: i64,
    tick: u64,
    finished: bool,
}

impl TrapezoidStepper {
    /// `tick_hz`: 1..=[`MAX_TICK_HZ`].
    pub fn new(p: &TrapezoidParams, tick_hz: u32) -> Result<Self, OutOfRange> {
        p.validate()?;
        OutOfRange::check("tick_hz", tick_hz.into(), 1, MAX_TICK_HZ.into())?;
        Ok(Self {
            lim: TickLimits::new(p, tick_hz),
            target: i64::from(p.steps) * ONE,
            position: 0,
            velocity: 0,
            tick: 0,
            finished: false,
        })
    }

    pub fn limits(&self) -> TickLimits {
        self.lim
    }

    /// The least distance still covered after a tick at velocity `w`: the
    /// chain w − d, w − 2d, ... down to the first term taken at or below the
    /// stop speed s (every term is then positive since s >= d). With
    /// m = ⌈(w − s)/d⌉ terms: m·w − d·m(m+1)/2.
    fn braking(&self, w: i64) -> i128 {
        let (s, d) = (i128::from(self.lim.stop()), i128::from(self.lim.decel));
        let w = i128::from(w);
        if w <= s {
            return 0;
        }
        let m = (w - s + d - 1) / d;
        m * w - d * m * (m + 1) / 2
    }

    /// The next tick's velocity: the largest w in the reachable range with
    /// w + braking(w) <= remaining. That function of w rises by at least 1
    /// per LSB, so when the remaining distance is below the stop speed it is
    /// taken in one tick, exactly.
    fn next_velocity(&self) -> i64 {
        let remaining = i128::from(self.target - self.position);
        let lo = if self.velocity <= self.lim.stop() {
            0
        } else {
            self.velocity - self.lim.decel
        };
        let hi = self
            .lim
            .max
            .min((self.velocity + self.lim.accel).max(self.lim.start));
        let fits = |w: i64| i128::from(w) + self.braking(w) <= remaining;
        if fits(hi) {
            return hi;
        }
        if !fits(lo) {
            // Unreachable: the previous tick left at least braking(v).
            return lo;
        }
        let (mut lo, mut hi) = (lo, hi);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if fits(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }
}

impl Iterator for TrapezoidStepper {
    type Item = TrapezoidSample;

    fn next(&mut self) -> Option<TrapezoidSample> {
        if self.finished {
            return None;
        }
        if self.tick == 0 {
            // The first sample is the rest before the move.
            self.tick = 1;
            self.finished = self.target == 0;
            return Some(TrapezoidSample::default());
        }
        let w = self.next_velocity();
        let phase = match w.cmp(&self.velocity) {
            _ if w == 0 => TrapezoidPhase::Rest,
            core::cmp::Ordering::Greater => TrapezoidPhase::Accel,
            core::cmp::Ordering::Equal => TrapezoidPhase::Cruise,
            core::cmp::Ordering::Less => TrapezoidPhase::Decel,
        };
        self.velocity = w;
        self.position += w;
        let s = TrapezoidSample {
            tick: self.tick,
            position: self.position,
            velocity: w,
            phase,
        };
        self.tick += 1;
        self.finished = w == 0 && self.position == self.target;
        Some(s)
    }
}
