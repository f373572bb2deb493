//! 7-segment jerk-limited S-curve of the STM32 + FPGA card (seed 004,
//! section 4, steps 1-5): jerk ±J, acceleration within ±A, velocity within
//! V, T1 = T3 and T5 = T7 (the same jerk ramps acceleration up and down).
//!
//! # Discrete model
//!
//! Every quantity is Q32.32 per servo tick (see [`super`]): each tick
//! applies a jerk j (|j| <= J) and
//!
//! ```text
//! a(k+1) = a(k) + j,   v(k+1) = v(k) + a(k+1),   p(k+1) = p(k) + v(k+1)
//! ```
//!
//! so v is the distance of a tick and a its change: the limits hold exactly
//! on the sampled integers.
//!
//! # Algorithm (steps 1-5 of the seed)
//!
//! 1. Initialise J, A, V and the target. (The seed also lists an initial
//!    speed; moves here start and end at rest.)
//! 2. Every tick compute the braking distance `dec` and compare it with the
//!    remaining distance Ls = Le − Lc. `dec` is the distance the braking law
//!    (below) covers from the state the next accelerating or cruising tick
//!    would reach.
//! 3. If Ls <= dec, decelerate; else accelerate toward V, or cruise at V.
//! 4. Recompute a, v, j and output.
//! 5. Stop when at rest on the target; else repeat from 2.
//!
//! Accelerating toward V and braking to 0 use one law, [`reach`]: the
//! largest next acceleration from which the velocity can still be brought to
//! the goal at full jerk without passing it. It reaches the goal velocity and
//! zero acceleration exactly, in integers.
//!
//! On the tick where step 3 first says "decelerate", the planner takes the
//! least braking that still does not stop short (a binary search between
//! braking and accelerating), so the braking law ends at or past the target,
//! by a fraction of a tick's travel. The sampler then scales every position
//! by target / planned end (<= 1), which lands exactly on the target
//! (position == target × 2^32, velocity 0) and only lowers velocity,
//! acceleration and jerk. Floors in that scaling move a sample by less than
//! one LSB, so the planner keeps J − 3 and A − 1 LSB as its limits and the
//! scaled samples stay within J and A.
//!
//! A short move that never reaches V (or A) follows from the same rules.
//!
//! # Cost
//!
//! `dec` ([`braking_distance`]) simulates the braking law, O(braking ticks).
//! An accelerating tick needs it only when the remaining distance is within
//! a cheap upper bound of it; a cruise reuses the last value. Planning (and
//! sampling) is so at worst O(ramp ticks²): under a millisecond for ramps of
//! a hundred ticks, about 0.1 s for 3000 on a PC; ramps longer than
//! [`MAX_RAMP_TICKS`] are refused.

use crate::{OutOfRange, ONE};

/// Jerk range, Q32.32 steps/tick³.
pub const JERK_RANGE: (i64, i64) = (1 << 8, 1 << 40);
/// Acceleration range, Q32.32 steps/tick².
pub const ACCEL_RANGE: (i64, i64) = (1 << 8, 1 << 44);
/// Velocity range, Q32.32 steps/tick (2^47 is 32768 steps/tick: above the
/// pulse generator's f/2 at 50 MHz and a 1 kHz tick).
pub const VELOCITY_RANGE: (i64, i64) = (1 << 8, 1 << 47);
/// Largest |distance|, whole steps (the pulse generator's position is a
/// signed 32-bit count).
pub const DISTANCE_MAX: i64 = i32::MAX as i64;
/// Longest acceleration ramp (0 to V) accepted, ticks.
pub const MAX_RAMP_TICKS: i64 = 1 << 12;

/// One move's limits and distance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SCurveParams {
    /// J, Q32.32 steps/tick³, in [`JERK_RANGE`].
    pub jerk: i64,
    /// A, Q32.32 steps/tick², in [`ACCEL_RANGE`].
    pub accel: i64,
    /// V, Q32.32 steps/tick, in [`VELOCITY_RANGE`].
    pub velocity: i64,
    /// Target, whole steps, signed (the sign is the direction).
    pub distance: i64,
}

impl SCurveParams {
    /// From steps/s³, steps/s², steps/s and a tick rate, rounded to nearest
    /// (out-of-range or NaN inputs give values [`SCurve::new`] refuses).
    pub fn from_physical(
        jerk: f64,
        accel: f64,
        velocity: f64,
        distance: i64,
        tick_hz: f64,
    ) -> Self {
        let q = |x: f64| (x * ONE as f64 + 0.5) as i64;
        Self {
            jerk: q(jerk / (tick_hz * tick_hz * tick_hz)),
            accel: q(accel / (tick_hz * tick_hz)),
            velocity: q(velocity / tick_hz),
            distance,
        }
    }

    /// Every parameter in its range and the ramp no longer than
    /// [`MAX_RAMP_TICKS`].
    pub fn validate(&self) -> Result<(), SCurveError> {
        OutOfRange::check("jerk", self.jerk, JERK_RANGE.0, JERK_RANGE.1)?;
        OutOfRange::check("accel", self.accel, ACCEL_RANGE.0, ACCEL_RANGE.1)?;
        OutOfRange::check(
            "velocity",
            self.velocity,
            VELOCITY_RANGE.0,
            VELOCITY_RANGE.1,
        )?;
        OutOfRange::check("distance", self.distance, -DISTANCE_MAX, DISTANCE_MAX)?;
        let ticks = ramp_ticks(self.jerk, self.accel, self.velocity);
        if ticks > MAX_RAMP_TICKS {
            return Err(SCurveError::TooLong {
                ramp_ticks: ticks,
                max: MAX_RAMP_TICKS,
            });
        }
        Ok(())
    }
}

/// Ticks to accelerate from rest to V at jerk J and acceleration A: an
/// upper bound (measured up to 1.54 times the ramp `reach` takes, so
/// TooLong can refuse a move whose real ramp is shorter than the limit).
fn ramp_ticks(j: i64, a: i64, v: i64) -> i64 {
    // Jerk ramp: to A, or to the peak of a ramp that reaches V without A.
    let t_j = ((a + j - 1) / j).min(((v + j - 1) / j).isqrt() + 1);
    let a_peak = a.min(j.saturating_mul(t_j)).max(1);
    2 * t_j + (v + a_peak - 1) / a_peak
}

/// Why an S-curve cannot be planned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SCurveError {
    OutOfRange(OutOfRange),
    /// The acceleration ramp would take `ramp_ticks` > `max` ticks.
    TooLong {
        ramp_ticks: i64,
        max: i64,
    },
}

impl From<OutOfRange> for SCurveError {
    fn from(e: OutOfRange) -> Self {
        Self::OutOfRange(e)
    }
}

impl core::fmt::Display for SCurveError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::OutOfRange(e) => e.fmt(f),
            Self::TooLong { ramp_ticks, max } => write!(
                f,
                "acceleration ramp of {ramp_ticks} ticks is longer than {max}"
            ),
        }
    }
}

impl core::error::Error for SCurveError {}

/// Which of the seven segments a tick belongs to, from the signs of its
/// acceleration and jerk.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Phase {
    /// Before the move (tick 0), and a null move. The last tick of a move,
    /// which brings the deceleration back to 0 at rest on the target, is
    /// T7.
    #[default]
    Rest,
    /// T1: jerk +J, acceleration rising.
    IncreasingAccel,
    /// T2: constant acceleration.
    ConstantAccel,
    /// T3: jerk −J, acceleration falling to 0.
    DecreasingAccel,
    /// T4: constant velocity.
    Cruise,
    /// T5: jerk −J, deceleration rising.
    IncreasingDecel,
    /// T6: constant deceleration.
    ConstantDecel,
    /// T7: jerk +J, deceleration falling to 0.
    DecreasingDecel,
}

impl Phase {
    /// 1..=7 for T1..T7, `None` at rest.
    pub fn number(self) -> Option<u8> {
        Some(match self {
            Self::Rest => return None,
            Self::IncreasingAccel => 1,
            Self::ConstantAccel => 2,
            Self::DecreasingAccel => 3,
            Self::Cruise => 4,
            Self::IncreasingDecel => 5,
            Self::ConstantDecel => 6,
            Self::DecreasingDecel => 7,
        })
    }

    /// The phase of a tick that changes the acceleration from `a0` to `a1`.
    fn of(a0: i64, a1: i64, v1: i64) -> Self {
        match (a1.signum(), (a1 - a0).signum()) {
            (1, 1) => Self::IncreasingAccel,
            (1, 0) => Self::ConstantAccel,
            (1, _) | (0, -1) => Self::DecreasingAccel,
            (0, 0) if v1 != 0 => Self::Cruise,
            (0, 0) => Self::Rest,
            (-1, -1) => Self::IncreasingDecel,
            (-1, 0) => Self::ConstantDecel,
            _ => Self::DecreasingDecel,
        }
    }
}

/// G(x) for x > 0 (below).
fn gain(x: i64, j: i64) -> i64 {
    let k = (x + j - 1) / j;
    k * x - j * k * (k - 1) / 2
}

/// Largest x >= 0 with G(x) <= e, where G(x) = Σ_{i>=0} max(0, x − iJ) is
/// the velocity an acceleration x adds this tick and while ramping down to 0
/// at full jerk. On x in ((k−1)J, kJ], G(x) = kx − J·k(k−1)/2.
///
/// i64 is enough: e is a velocity difference (< 2^48 with V <= 2^47) and
/// every product below is at most e + J·(k+1) < 2^50.
fn largest_gain(e: i64, j: i64) -> i64 {
    // k = the largest k >= 1 with G((k−1)J) = J·k(k−1)/2 <= e.
    let mut k = (1 + 8 * (e / j) as u64).isqrt().div_ceil(2).max(1) as i64;
    while k > 1 && j * k * (k - 1) / 2 > e {
        k -= 1;
    }
    while j * (k + 1) * k / 2 <= e {
        k += 1;
    }
    (e + j * k * (k - 1) / 2) / k
}

/// The next acceleration that drives velocity `v` (acceleration `a`) to
/// `goal` with acceleration 0, jerk within `j`, acceleration within `amax`:
/// the largest step toward the goal after which a full-jerk ramp back to 0
/// does not pass it. From a state where that is possible (every state this
/// law or the planner produces) it never passes the goal and ends on it
/// exactly: once the remaining velocity is at most J it is taken in one tick.
pub fn reach(v: i64, a: i64, goal: i64, j: i64, amax: i64) -> i64 {
    // Mirror so that the goal is above.
    let (e, a, sign) = if goal >= v {
        (goal - v, a, 1)
    } else {
        (v - goal, -a, -1)
    };
    let hi = (a + j).min(amax);
    let lo = a - j;
    let x = if hi <= 0 || gain(hi, j) <= e {
        // The full step fits (the usual case on ramps and holds).
        hi
    } else {
        largest_gain(e, j).max(lo)
    };
    sign * x
}

/// The seed's `dec`: the distance (Q32.32 steps) the braking law — [`reach`]
/// toward velocity 0 — covers from velocity `v` and acceleration `a` until at
/// rest. `v` >= 0 and a state the law can stop from without reversing (every
/// state of a planned move is one).
pub fn braking_distance(v: i64, a: i64, j: i64, amax: i64) -> i128 {
    let (mut v, mut a, mut d) = (v, a, 0i128);
    while v != 0 || a != 0 {
        a = reach(v, a, 0, j, amax);
        v += a;
        d += i128::from(v);
    }
    d
}

/// A cheap upper bound of [`braking_distance`] for a >= 0: the peak speed
/// E = v + G(a) (a ramping down at full jerk) times a bound of the braking
/// ticks: a/J to bring a to 0, A/J up to −A, E/A at −A, and the taper, at
/// most A/J plus the time a triangular stop from E takes, 2√(2E/J), with a
/// few ticks for rounding.
fn braking_bound(v: i64, a: i64, j: i64, amax: i64) -> i128 {
    let e = i128::from(v) + i128::from(if a > 0 { gain(a, j) } else { 0 });
    let (j, amax, a) = (i128::from(j), i128::from(amax), i128::from(a.max(0)));
    let ticks = (a + j - 1) / j
        + 3 * ((amax + j - 1) / j)
        + (e + amax - 1) / amax
        + 2 * ((2 * e / j + 1).isqrt() + 1)
        + 8;
    e * ticks
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Planner {
    j: i64,
    amax: i64,
    vmax: i64,
    target: i128,
    p: i128,
    v: i64,
    a: i64,
    braking: bool,
    tick: u64,
    /// Last braking distance asked for: (v, a, dec).
    cache: Option<(i64, i64, i128)>,
}

impl Planner {
    fn new(p: &SCurveParams) -> Self {
        Self {
            // Margins for the floors of the final scaling (module docs).
            j: p.jerk - 3,
            amax: p.accel - 1,
            vmax: p.velocity,
            target: i128::from(p.distance.unsigned_abs() as i64) * i128::from(ONE),
            p: 0,
            v: 0,
            a: 0,
            braking: false,
            tick: 0,
            cache: None,
        }
    }

    fn done(&self) -> bool {
        self.target == 0 || (self.braking && self.v == 0 && self.a == 0)
    }

    /// Distance the braking law covers from (v, a) until at rest.
    fn dec(&mut self, v: i64, a: i64) -> i128 {
        if let Some((cv, ca, d)) = self.cache {
            if (cv, ca) == (v, a) {
                return d;
            }
        }
        let d = braking_distance(v, a, self.j, self.amax);
        self.cache = Some((v, a, d));
        d
    }

    /// Braking from the state one tick with acceleration `x` reaches would
    /// end at or past the target: the remaining distance there is at most
    /// [`Planner::threshold`].
    fn late(&mut self, x: i64) -> bool {
        let w = self.v + x;
        let remaining = self.target - self.p - i128::from(w);
        // Far from the deceleration point the bound settles it.
        if x >= 0 && remaining > braking_bound(w, x, self.j, self.amax) {
            return false;
        }
        remaining <= self.dec(w, x)
    }

    /// The remaining distance at or below which state (w, x) is late:
    /// min(bound, dec) for x >= 0, as [`Planner::late`] decides (so skipping
    /// the cruise with it takes the same ticks even if the bound were
    /// wrong; a late decision always means remaining <= dec).
    fn threshold(&mut self, w: i64, x: i64) -> i128 {
        let dec = self.dec(w, x);
        if x >= 0 {
            dec.min(braking_bound(w, x, self.j, self.amax))
        } else {
            dec
        }
    }

    /// One tick (steps 2-4); returns its phase.
    fn step(&mut self) -> Phase {
        let x = if self.braking {
            reach(self.v, self.a, 0, self.j, self.amax)
        } else {
            let accel = reach(self.v, self.a, self.vmax, self.j, self.amax);
            if !self.late(accel) {
                accel
            } else {
                // Step 3 says decelerate: the least braking that still ends
                // at or past the target.
                self.braking = true;
                let brake = reach(self.v, self.a, 0, self.j, self.amax);
                if self.late(brake) {
                    brake
                } else {
                    // `early` is not late, `late` is; both are within one
                    // jerk of a, and so is everything between.
                    let (mut early, mut late) = (brake, accel);
                    while (late - early).abs() > 1 {
                        let mid = early + (late - early) / 2;
                        if self.late(mid) {
                            late = mid;
                        } else {
                            early = mid;
                        }
                    }
                    late
                }
            }
        };
        let phase = Phase::of(self.a, x, self.v + x);
        self.a = x;
        self.v += x;
        self.p += i128::from(self.v);
        self.tick += 1;
        phase
    }

    /// Skips the cruise ticks before the deceleration point at once (the
    /// same ticks `step` would take one by one).
    fn skip_cruise(&mut self) {
        if self.braking || self.a != 0 || self.v != self.vmax {
            return;
        }
        let slack = self.target - self.p - self.threshold(self.v, 0);
        if slack >= i128::from(self.v) {
            let n = slack / i128::from(self.v);
            self.p += n * i128::from(self.v);
            self.tick += n as u64;
        }
    }
}

/// A planned S-curve move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SCurve {
    params: SCurveParams,
    start: Planner,
    planned_end: i128,
    ticks: u64,
    decel_tick: u64,
}

impl SCurve {
    /// Plans the move (runs the planner once, skipping the cruise, to find
    /// where its braking ends).
    pub fn new(params: SCurveParams) -> Result<Self, SCurveError> {
        params.validate()?;
        let start = Planner::new(&params);
        let mut pl = start;
        let mut decel_tick = 0;
        let mut iterations = 0;
        while !pl.done() {
            // Ramps are bounded by validate(); the cruise is skipped.
            iterations += 1;
            assert!(
                iterations < 4 * MAX_RAMP_TICKS + 64,
                "S-curve planner does not converge: {params:?}"
            );
            pl.skip_cruise();
            let braking = pl.braking;
            pl.step();
            if pl.braking && !braking {
                decel_tick = pl.tick;
            }
        }
        Ok(Self {
            params,
            start,
            planned_end: pl.p,
            ticks: pl.tick,
            decel_tick,
        })
    }

    pub fn params(&self) -> SCurveParams {
        self.params
    }

    /// Ticks from the start until at rest on the target (the last sample's
    /// tick).
    pub fn ticks(&self) -> u64 {
        self.ticks
    }

    /// The tick at which deceleration began (0 for a null move).
    pub fn decel_tick(&self) -> u64 {
        self.decel_tick
    }

    /// The planner's braking end, Q32.32 steps (magnitude, >= the target);
    /// the samples are scaled by |target| / this.
    pub fn planned_end(&self) -> i128 {
        self.planned_end
    }

    /// The per-tick samples, tick 0 (rest) to [`SCurve::ticks`].
    pub fn samples(&self) -> SCurveSampler {
        SCurveSampler {
            planner: self.start,
            planned_end: self.planned_end,
            sign: if self.params.distance < 0 { -1 } else { 1 },
            position: 0,
            velocity: 0,
            finished: false,
            started: false,
        }
    }
}

/// One tick of an S-curve (Q32.32, signed by the direction).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SCurveSample {
    pub tick: u64,
    /// Steps.
    pub position: i64,
    /// Distance of the tick ending here, steps/tick.
    pub velocity: i64,
    /// Change of velocity over the tick ending here, steps/tick².
    pub accel: i64,
    pub phase: Phase,
}

impl SCurveSample {
    /// The whole steps commanded so far (floor of the position).
    pub fn steps(&self) -> i64 {
        crate::whole_steps(self.position)
    }
}

/// Iterator over an [`SCurve`]'s samples; O(1) per cruise tick, O(braking
/// ticks) per accelerating tick, no heap.
#[derive(Clone, Debug)]
pub struct SCurveSampler {
    planner: Planner,
    planned_end: i128,
    sign: i64,
    position: i64,
    velocity: i64,
    finished: bool,
    started: bool,
}

impl Iterator for SCurveSampler {
    type Item = SCurveSample;

    fn next(&mut self) -> Option<SCurveSample> {
        if self.finished {
            return None;
        }
        if !self.started {
            self.started = true;
            self.finished = self.planner.done();
            return Some(SCurveSample::default());
        }
        let phase = self.planner.step();
        // planned_end >= target and both < 2^64, so the product fits.
        let scaled = (self.planner.p * self.planner.target / self.planned_end) as i64;
        let position = self.sign * scaled;
        let velocity = position - self.position;
        let accel = velocity - self.velocity;
        self.position = position;
        self.velocity = velocity;
        self.finished = self.planner.done();
        Some(SCurveSample {
            tick: self.planner.tick,
            position,
            velocity,
            accel,
            phase,
        })
    }
}

#[cfg(test)]
mod tests;
