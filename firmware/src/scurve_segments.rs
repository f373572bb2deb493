//! A 7-phase jerk-limited S-curve planned straight into pulse-generator
//! segments: one segment per phase, SEG_JERK carrying the jerk
//! (docs/pulse_generator.md, "Ramps"), so a move is at most 7 segments per
//! axis instead of one per servo tick.
//!
//! # Plan
//!
//! The phases of the STM32 + FPGA seed (jerk +J, 0, −J to the cruise rate,
//! the cruise, then −J, 0, +J to rest) take their peak acceleration and
//! rate from the continuous S-curve for the limits and the distance. The
//! move engine ends a segment on its last step, not on a clock, so the
//! planner follows the engine clock by clock ([`EngineState`], bit-exact
//! with the model) and ends each phase on the last step before its goal
//! (the peak acceleration; the rate from which the ramp down reaches the
//! peak rate; zero acceleration); the next phase starts from the rate and
//! acceleration the engine reached there (their fraction bits dropped, as a
//! load does). As the jerk changes on steps only, it is at most
//! (A³/6)^(1/2): from rest the first step comes at (6·J²)^(1/3), and a
//! steeper jerk would pass A before it. The cruise takes as
//! many steps as make the braking phases, followed the same way, reach the
//! target: the least number with which they get there, so the last segment
//! stops on the target at most about one step before its rate would reach
//! 0. The signed steps of the segments sum to the distance exactly.
//!
//! [`Plan::position`] is the planned profile: at every clock, the position
//! the segments command with exact sums (the engine rounds its rate and
//! acceleration to whole LSBs), with the one load clock between segments
//! at rest. The engine's step count is within one step of it at every
//! clock (the rounding, to nearest since a load holds half an LSB, drifts
//! by 10^-6 steps in the tests).
//!
//! Planning follows every clock of the ramps once per cruise length tried
//! (a bisection: log2 of the steps), the cruise itself in closed form: a
//! few milliseconds on a PC for the moves of `firmware/tests`.

use crate::segments::RATE_MAX;
use crate::OutOfRange;
use arrayvec::ArrayVec;
use motionhdl_spec::pulse::{Segment, ACCEL_FRAC_BITS, LOAD_FRACTION};

/// 2^e, exactly.
fn pow2(e: i32) -> f64 {
    libm::ldexp(1.0, e)
}

/// The correctly rounded square root (libm's: `core` has none, and the
/// same code plans on the MCU and the host).
fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
}

/// Longest move planned, clocks (about 43 s at 50 MHz).
pub const PLAN_CLOCK_LIMIT: u64 = 1 << 31;
/// Largest |distance|, steps.
pub const PLAN_DISTANCE_MAX: i64 = i32::MAX as i64;

/// Limits in the move engine's own units (docs/pulse_generator.md):
/// `rate` in SEG_RATE LSBs (2^-32 steps/clock), `accel` in SEG_ACCEL LSBs
/// (2^-48 steps/clock²), `jerk` in SEG_JERK LSBs (2^-64 steps/clock³).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EngineLimits {
    pub rate: i32,
    pub accel: i32,
    pub jerk: i32,
}

impl EngineLimits {
    /// From steps/s, steps/s² and steps/s³ at `clock_hz`, rounded down
    /// (values out of range are refused by [`plan`]).
    pub fn from_physical(rate: f64, accel: f64, jerk: f64, clock_hz: f64) -> Self {
        let lsb = |x: f64, per_clock: f64, bits: i32| {
            (x / per_clock * pow2(bits)).clamp(0.0, i32::MAX as f64) as i32
        };
        Self {
            rate: lsb(rate, clock_hz, 32),
            accel: lsb(accel, clock_hz * clock_hz, 48),
            jerk: lsb(jerk, clock_hz * clock_hz * clock_hz, 64),
        }
    }

    fn validate(&self) -> Result<(), OutOfRange> {
        OutOfRange::check("rate", self.rate.into(), 1 << 8, RATE_MAX)?;
        OutOfRange::check("accel", self.accel.into(), 1, i32::MAX.into())?;
        OutOfRange::check("jerk", self.jerk.into(), 1, i32::MAX.into())?;
        Ok(())
    }
}

/// Why a move cannot be planned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanError {
    OutOfRange(OutOfRange),
    /// The move would take more than [`PLAN_CLOCK_LIMIT`] clocks.
    TooLong,
}

impl From<OutOfRange> for PlanError {
    fn from(e: OutOfRange) -> Self {
        Self::OutOfRange(e)
    }
}

impl core::fmt::Display for PlanError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::OutOfRange(e) => e.fmt(f),
            Self::TooLong => write!(f, "the move takes more than 2^31 clocks"),
        }
    }
}

impl core::error::Error for PlanError {}

/// The move engine's running registers in the magnitude frame, clock by
/// clock: the rate and the acceleration with their 16 fraction bits, the
/// NCO's phase, and the steps and clocks so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EngineState {
    pub rate: i64,
    pub accel: i64,
    pub phase: u64,
    pub steps: u64,
    pub clock: u64,
    /// Backwards: the engine floors the negative registers toward −∞, so
    /// their magnitudes round up.
    pub backward: bool,
}

impl EngineState {
    /// Loads `seg` (magnitude frame): the load clock runs at rate 0.
    fn load(&mut self, seg: &Segment) {
        // The load's half LSB, negated backwards.
        let half = if self.backward {
            -LOAD_FRACTION
        } else {
            LOAD_FRACTION
        };
        self.rate = (i64::from(seg.rate) << ACCEL_FRAC_BITS) + half;
        self.accel = (i64::from(seg.accel) << ACCEL_FRAC_BITS) + half;
        self.clock += 1;
    }

    /// One advancing clock of a segment with `jerk`; true on a step.
    /// `None` once the rate would be negative or above the NCO's range.
    fn advance(&mut self, jerk: i32) -> Option<bool> {
        let nco = self.whole(self.rate);
        if !(0..=RATE_MAX).contains(&nco) {
            return None;
        }
        self.phase += nco as u64;
        let step = self.phase >> 32 != 0;
        self.phase &= 0xFFFF_FFFF;
        self.steps += u64::from(step);
        self.rate += self.whole(self.accel);
        self.accel += i64::from(jerk);
        self.clock += 1;
        Some(step)
    }

    /// ⌊x / 2^16⌋ of the signed register, in the magnitude frame.
    fn whole(&self, x: i64) -> i64 {
        if self.backward {
            -((-x) >> ACCEL_FRAC_BITS)
        } else {
            x >> ACCEL_FRAC_BITS
        }
    }

    /// Loads `seg` (no acceleration, no jerk) and runs it to its `n`th
    /// step, in closed form: at a constant rate r the steps come where the
    /// phase passes multiples of 2^32.
    fn cruise(&mut self, seg: &Segment, n: u64) -> Option<()> {
        debug_assert!(seg.accel == 0 && seg.jerk == 0 && n > 0);
        self.load(seg);
        let r = u64::try_from(self.whole(self.rate))
            .ok()
            .filter(|&r| r > 0)?;
        let clocks = ((n << 32) - self.phase).div_ceil(r);
        self.phase = self.phase + clocks * r - (n << 32);
        self.steps += n;
        self.clock += clocks;
        Some(())
    }

    /// The segment that continues from here with `jerk` (fractions dropped).
    fn segment(&self, jerk: i32) -> Segment {
        let whole = |x: i64| self.whole(x).clamp(i32::MIN.into(), i32::MAX.into()) as i32;
        Segment {
            steps: 0,
            rate: whole(self.rate).max(0),
            accel: whole(self.accel),
            jerk,
        }
    }

    /// Loads a segment with `jerk` from here and runs it to its last step
    /// before `stop` holds (at most `cap`; a rate leaving the NCO's range
    /// ends it at the step before). A phase with no step by then is left
    /// out, unless `run_on` (the first, from rest: it runs on to its first
    /// step). Returns the segment with its steps, the state after its last
    /// step, and 1 if it stopped on `cap` with a step still to come before
    /// `stop` (else 0); `None` if it is left out.
    fn phase(&self, jerk: i32, stop: Stop, cap: u64, run_on: bool) -> Option<PhaseRun> {
        let mut seg = self.segment(jerk);
        let mut s = *self;
        s.load(&seg);
        if stop.holds(&s) {
            return None;
        }
        let start = s.steps;
        let mut last: Option<EngineState> = None;
        while s.clock < PLAN_CLOCK_LIMIT && !((last.is_some() || !run_on) && stop.holds(&s)) {
            match s.advance(jerk) {
                None => break,
                Some(true) if last.is_some_and(|l| l.steps - start == cap) => {
                    let last = last?;
                    seg.steps = (last.steps - start) as u32;
                    return Some((seg, last, u64::from(!stop.holds(&s))));
                }
                Some(true) => last = Some(s),
                Some(false) => {}
            }
        }
        let last = last?;
        seg.steps = (last.steps - start) as u32;
        Some((seg, last, 0))
    }
}

/// Where a phase ends: when any of its conditions holds (the engine's
/// register units: rate 2^-48, accel 2^-64 steps per clock, per clock²).
#[derive(Clone, Copy, Debug, Default)]
struct Stop {
    accel_at_least: Option<i64>,
    accel_at_most: Option<i64>,
    /// The rate the acceleration would add (or take) ramped to 0 at the
    /// jerk reaches at least (`true`) or at most (`false`) the target.
    rate: Option<(i64, bool)>,
    jerk: i64,
}

impl Stop {
    fn holds(&self, s: &EngineState) -> bool {
        let a = i128::from(s.accel);
        let ramp = (a * a / (2 * i128::from(self.jerk.max(1)))) >> ACCEL_FRAC_BITS;
        let r = i128::from(s.rate);
        self.accel_at_least.is_some_and(|x| s.accel >= x)
            || self.accel_at_most.is_some_and(|x| s.accel <= x)
            || self.rate.is_some_and(|(target, up)| {
                if up {
                    r + ramp >= i128::from(target)
                } else {
                    r - ramp <= i128::from(target)
                }
            })
    }
}

/// A phase's segment, the state after its last step, and whether it
/// stopped on its cap with steps left to give (1) or not (0).
type PhaseRun = (Segment, EngineState, u64);
/// At most 3 phases up, the cruise and 3 down.
type Phases = ArrayVec<PhaseRun, MAX_SEGMENTS>;

/// The most segments a plan has: one per phase.
pub const MAX_SEGMENTS: usize = 7;

/// A planned move: the segments and where each starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// Signed: the direction is the sign of each segment's rate (or accel,
    /// or jerk); at most 7.
    pub segments: ArrayVec<Segment, MAX_SEGMENTS>,
    /// The clock each segment loads on, counted from the first load.
    pub starts: ArrayVec<u64, MAX_SEGMENTS>,
    /// The clock after the last segment's last step.
    pub clocks: u64,
    /// +1 or −1.
    pub direction: i64,
}

impl Plan {
    /// The planned position at clock `k` (after k clocks from the first
    /// load), in 2^-64 steps, signed: each segment's rate rate·2^32 +
    /// n·accel·2^16 + jerk·n(n−1)/2 (2^-64 steps/clock) summed over its
    /// advancing clocks, without the engine's floors.
    pub fn position(&self, k: u64) -> i128 {
        let mut p = 0i128;
        for (i, seg) in self.segments.iter().enumerate() {
            let end = self.starts.get(i + 1).copied().unwrap_or(self.clocks);
            let n = i128::from(k.min(end).saturating_sub(self.starts[i] + 1));
            let (r, a, j) = magnitude(seg, self.direction);
            p += n * (r << 32) + (a << 16) * n * (n - 1) / 2 + j * n * (n - 1) * (n - 2) / 6;
        }
        p * i128::from(self.direction)
    }
}

fn magnitude(seg: &Segment, dir: i64) -> (i128, i128, i128) {
    let d = i128::from(dir);
    (
        i128::from(seg.rate) * d,
        i128::from(seg.accel) * d,
        i128::from(seg.jerk) * d,
    )
}

/// The continuous S-curve for the limits and the distance: the peak
/// acceleration (2^-64 steps/clock²) and the peak rate (2^-48 steps/clock).
fn peaks(distance: f64, lim: &EngineLimits) -> (i64, i64) {
    let j = f64::from(lim.jerk) * pow2(-64);
    let a = f64::from(lim.accel) * pow2(-48);
    let v = f64::from(lim.rate) * pow2(-32);
    let mut t1 = (a / j).min(sqrt(v / j));
    let mut t2 = (v / (j * t1) - t1).max(0.0);
    // A short move: less time at A, then a lower peak acceleration.
    if j * t1 * (t1 + t2) * (2.0 * t1 + t2) > distance {
        t2 = (sqrt(t1 * t1 + 4.0 * distance / (j * t1)) - 3.0 * t1).max(0.0) / 2.0;
        if t2 <= 0.0 {
            t1 = libm::cbrt(distance / (2.0 * j));
        }
    }
    let peak_accel = (j * t1 * pow2(64)).min(f64::from(lim.accel) * 65536.0);
    let peak_rate = (j * t1 * (t1 + t2) * pow2(48)).min(f64::from(lim.rate) * 65536.0);
    (peak_accel as i64, peak_rate as i64)
}

/// Plans a move of `distance` steps from rest to rest within `lim`.
pub fn plan(distance: i64, lim: EngineLimits) -> Result<Plan, PlanError> {
    lim.validate()?;
    OutOfRange::check("distance", distance, -PLAN_DISTANCE_MAX, PLAN_DISTANCE_MAX)?;
    let direction = if distance < 0 { -1 } else { 1 };
    let d = distance.unsigned_abs();
    let mut out = Plan {
        segments: ArrayVec::new(),
        starts: ArrayVec::new(),
        clocks: 0,
        direction,
    };
    if d == 0 {
        return Ok(out);
    }
    // The jerk changes on steps only: from rest the first step comes when
    // J·t³/6 = 1, at acceleration (6·J²)^(1/3), so a jerk above
    // (A³/6)^(1/2) would ramp past A before any step could end the ramp.
    let a = f64::from(lim.accel) * pow2(-48);
    let steepest = (sqrt(a * a * a / 6.0) * pow2(64)).max(1.0);
    let lim = EngineLimits {
        jerk: lim.jerk.min(steepest.min(f64::from(i32::MAX)) as i32),
        ..lim
    };
    // A landing that stops short of the braking's natural end (the
    // accelerating phases went too far) is planned again for less distance.
    let mut aim = d as f64;
    let mut phases = ArrayVec::new();
    for _ in 0..24 {
        let (p, short) = fastest_phases(d, aim, &lim, direction < 0)?;
        phases = p;
        if !short {
            break;
        }
        aim *= 0.9;
    }
    let mut start = 0;
    for (seg, end, _) in &phases {
        out.starts.push(start);
        out.segments.push(signed(seg, direction));
        start = end.clock;
    }
    out.clocks = start;
    Ok(out)
}

/// The phases for `d` steps aimed at `aim` (see [`plan_phases`]), at the
/// full jerk or at [`whole_step_jerk`], whichever lands sooner.
fn fastest_phases(
    d: u64,
    aim: f64,
    lim: &EngineLimits,
    backward: bool,
) -> Result<(Phases, bool), PlanError> {
    let (accel, rate) = peaks(aim, lim);
    let full = i64::from(lim.jerk);
    let mut best = plan_phases(d, full, accel, rate, backward)?;
    let fit = whole_step_jerk(full, accel);
    if fit != full {
        let other = plan_phases(d, fit, accel, rate, backward)?;
        let end = |p: &(Phases, bool)| (p.1, p.0.last().map_or(0, |r| r.1.clock));
        if end(&other) < end(&best) {
            best = other;
        }
    }
    Ok(best)
}

/// The jerk, at most `jerk`, whose ramp from rest reaches `accel` (both
/// 2^-64 units) just after a whole step; `jerk` if the full jerk reaches
/// it before the first step. The ramp ends on a step, and from rest the
/// k-th step comes at acceleration (6·k·J²)^(1/3): at the full jerk the
/// last step before `accel` can fall far short of it when steps are sparse
/// (measured: 80 % of the limit at k = 1, a move 10 % slower than the
/// continuous S-curve), where a jerk 1 % lower reaches it at k = 2.
fn whole_step_jerk(jerk: i64, accel: i64) -> i64 {
    let (j, a) = (jerk as f64 * pow2(-64), accel as f64 * pow2(-64));
    let k = a * a * a / (6.0 * j * j);
    if k < 1.0 {
        return jerk;
    }
    // Just under, so the k-th step comes before the ramp reaches `accel`.
    let fit = sqrt(a * a * a / (6.0 * libm::ceil(k))) * (1.0 - 1e-4) * pow2(64);
    jerk.min(fit as i64).max(1)
}

/// The phases for `d` steps at `jerk` up to `accel` and `rate`, and
/// whether the landing stopped short of the braking's natural end.
fn plan_phases(
    d: u64,
    jerk: i64,
    accel: i64,
    rate: i64,
    backward: bool,
) -> Result<(Phases, bool), PlanError> {
    let j = jerk as i32;
    let mut phases = ArrayVec::new();
    let mut s = EngineState {
        backward,
        ..EngineState::default()
    };
    let up = Stop {
        rate: Some((rate, true)),
        jerk,
        ..Stop::default()
    };
    // The first phase also ends where the ramp down would reach the peak
    // rate (a move too short to reach the peak acceleration).
    let first = Stop {
        accel_at_least: Some(accel),
        ..up
    };
    let last = Stop {
        accel_at_most: Some(0),
        ..Stop::default()
    };
    for (jj, stop) in [(j, first), (0, up), (-j, last)] {
        if let Some(run) = s.phase(jj, stop, d - s.steps, s.steps == 0) {
            s = run.1;
            phases.push(run);
        }
        if s.steps == d {
            return Ok((phases, true));
        }
    }
    let top = phases.first().map_or(accel, |p| p.1.accel);
    // The cruise holds its rate: the acceleration left by the last step of
    // the ramp down (short of 0) is dropped.
    let cruise = Segment {
        accel: 0,
        ..s.segment(0)
    };
    let (n, braking) = land(&s, cruise, d, jerk, top).ok_or(PlanError::TooLong)?;
    if n > 0 {
        let mut c = s;
        c.cruise(&cruise, n).ok_or(PlanError::TooLong)?;
        phases.push((
            Segment {
                steps: n as u32,
                ..cruise
            },
            c,
            0,
        ));
    }
    let short = braking.last().is_some_and(|b| b.2 != 0);
    phases.extend(braking);
    if phases.last().is_some_and(|p| p.1.clock >= PLAN_CLOCK_LIMIT) {
        return Err(PlanError::TooLong);
    }
    Ok((phases, short))
}

/// The least cruise steps (from `s`, at `cruise`'s rate) after which the
/// braking phases (−J to −`top`, constant until the ramp to 0 would stop
/// the rate, +J until the rate's lowest point) reach `d` steps; those
/// steps and the braking phases. `None` if no cruise length does.
fn land(s: &EngineState, cruise: Segment, d: u64, jerk: i64, top: i64) -> Option<(u64, Phases)> {
    let j = jerk as i32;
    let brake = |n: u64| -> Option<(bool, Phases)> {
        let mut c = *s;
        if n > 0 {
            c.cruise(&cruise, n)?;
        }
        let down = Stop {
            rate: Some((0, false)),
            jerk,
            ..Stop::default()
        };
        let first = Stop {
            accel_at_most: Some(-top),
            ..down
        };
        let rest = Stop {
            accel_at_least: Some(0),
            ..Stop::default()
        };
        let mut out = ArrayVec::new();
        for (jj, stop) in [(-j, first), (0, down), (j, rest)] {
            if c.steps == d {
                break;
            }
            if let Some(run) = c.phase(jj, stop, d - c.steps, false) {
                c = run.1;
                out.push(run);
            }
        }
        Some((c.steps == d, out))
    };
    // Braking reaches fewer steps the sooner it starts: bisect on the
    // cruise's length for the least that reaches the target.
    let (mut lo, mut hi) = (0u64, d - s.steps);
    match brake(0)? {
        (true, phases) => return Some((0, phases)),
        _ if cruise.rate == 0 => return None,
        _ => {}
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if brake(mid)?.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some((hi, brake(hi)?.1))
}

fn signed(seg: &Segment, dir: i64) -> Segment {
    let d = dir as i32;
    Segment {
        steps: seg.steps,
        rate: seg.rate * d,
        accel: seg.accel * d,
        jerk: seg.jerk * d,
    }
}
