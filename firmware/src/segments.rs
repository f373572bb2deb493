//! A profile sampled per servo tick, as segments for the FPGA pulse
//! generator's move FIFO ([`motionhdl_spec::pulse::Segment`]).
//!
//! The pulse generator's NCO commands steps at rate/2^32 steps per clock
//! (|rate| <= 2^31); a segment starts the NCO at `rate`, adds `accel` (16
//! fraction bits: 2^-16 of a rate LSB) to its rate on every clock the NCO
//! advances, and `jerk` to its accel, and ends once it has commanded
//! `steps` steps; the sign of the rate is the direction. The move engine spends one clock
//! loading each segment (the NCO stands still on it) and the NCO's phase
//! carries over from one segment to the next; the segment's copy out of the
//! FIFO's RAM takes 4 clocks, which a tick-long segment always covers. The
//! FIFO holds [`motionhdl_spec::pulse::SEGMENT_FIFO_DEPTH`] segments, fewer
//! than a move has ticks; the firmware streams segments as it drains, which
//! is why [`SegmentBuilder`] is a streaming converter with no heap.
//!
//! # Conversion
//!
//! Positions come as fixed point with `frac_bits` fractional bits (0 for
//! whole steps, 32 for the Q32.32 profiles of [`super`]), one per tick; the
//! axis is at rest before the first and after the last. A tick's step count
//! is the difference of the floors of its end positions, so the segments'
//! signed steps add up to floor(last) − floor(first) exactly. For each tick
//! that has steps, one segment:
//!
//! * `steps` = |Δ whole steps|, the direction its sign;
//! * `rate` = the velocity at the tick's start, estimated as the central
//!   difference (p(k+1) − p(k−1))/2 of the positions, in steps per clock ×
//!   2^32 (C = clock_hz / tick_hz clocks per tick, floor);
//! * `accel` = 2^16·(end rate − start rate) / (C − 1), truncated toward 0:
//!   the linear change that reaches the end velocity (the central difference
//!   at the tick's end) over the tick's advancing clocks (one of the C goes
//!   to loading the segment); `jerk` = 0.
//!
//! One LSB of accel is 2^-48 steps/clock² (about 8.9 steps/s² at 50 MHz),
//! so the truncation loses less than a thousandth of a step over a tick.
//! The steepest is 2^31 LSBs (about 1.9·10^10 steps/s²); a steeper ramp is
//! clamped to it and its start rate raised by half the part cut off, so
//! the segment keeps its mean rate and its steps per tick.
//!
//! A tick with no whole step (slow motion) gets no segment of its own: it
//! is merged into the next segment, whose ramp then runs from the first
//! merged tick's start velocity over m·C − 1 clocks for m ticks.
//!
//! # Timing
//!
//! The NCO commands steps at its own pace, so a segment ends when its last
//! step is commanded, which may be before or after the tick's end: a segment
//! may take more or fewer clocks than its ticks (the next one then starts
//! that much earlier or later). [`segment_clocks`] gives the exact count,
//! assuming the step output never holds the NCO back (its queue never
//! fills: step timing fast enough for the rate). When the
//! linear ramp would pass zero rate before the segment's steps are out (the
//! direction would turn) or leave the i32 range, the builder lowers |accel|
//! to the largest value that completes (and, where the start rate is 0 and
//! the ramp does not rise, uses a constant rate that covers the steps in the
//! tick's clocks); [`SegmentBuilder::adjusted`] counts those segments.

use crate::OutOfRange;
use motionhdl_spec::pulse::{Segment, ACCEL_FRAC_BITS, LOAD_FRACTION};

/// Largest |rate| the builder emits: 2^31 − 1, so that both directions are
/// representable as a positive or negative i32 (the NCO takes up to 2^31).
pub const RATE_MAX: i64 = i32::MAX as i64;
/// Longest segment [`segment_clocks`] follows (about 65 days at 50 MHz).
pub const CLOCK_LIMIT: u64 = 1 << 48;
/// Longest segment with a jerk [`segment_clocks`] follows: it runs those
/// clock by clock (about 86 s at 50 MHz).
pub const JERK_CLOCK_LIMIT: u64 = 1 << 32;

/// Clock rates and the NCO's phase at the start.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SegmentConfig {
    /// Pulse generator clock, Hz.
    pub clock_hz: u32,
    /// Servo tick rate, Hz: 1..=clock_hz/4.
    pub tick_hz: u32,
    /// NCO phase when the first segment starts (0 after reset).
    pub phase: u32,
}

impl Default for SegmentConfig {
    /// 50 MHz clock, 1 kHz tick, phase 0.
    fn default() -> Self {
        Self {
            clock_hz: 50_000_000,
            tick_hz: 1_000,
            phase: 0,
        }
    }
}

impl SegmentConfig {
    pub fn validate(&self) -> Result<(), OutOfRange> {
        OutOfRange::check("clock_hz", self.clock_hz.into(), 4, u32::MAX.into())?;
        OutOfRange::check(
            "tick_hz",
            self.tick_hz.into(),
            1,
            (self.clock_hz / 4).into(),
        )?;
        Ok(())
    }

    /// C = clock_hz / tick_hz, floor.
    pub fn clocks_per_tick(&self) -> u64 {
        u64::from(self.clock_hz / self.tick_hz)
    }
}

/// Why a profile cannot be converted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentError {
    Config(OutOfRange),
    /// At tick `tick` the profile needs |rate| = `rate` > `max`: faster than
    /// the NCO can step.
    TooFast {
        tick: u64,
        rate: i64,
        max: i64,
    },
}

impl From<OutOfRange> for SegmentError {
    fn from(e: OutOfRange) -> Self {
        Self::Config(e)
    }
}

impl core::fmt::Display for SegmentError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Config(e) => e.fmt(f),
            Self::TooFast { tick, rate, max } => {
                write!(f, "tick {tick} needs |rate| {rate}, above {max}")
            }
        }
    }
}

impl core::error::Error for SegmentError {}

/// The direction a segment steps: the sign of its rate, or of its accel
/// when the rate starts at 0, or of its jerk when both do.
pub fn direction(seg: &Segment) -> i64 {
    [seg.rate, seg.accel, seg.jerk]
        .into_iter()
        .find(|&x| x != 0)
        .map_or(0, |x| i64::from(x.signum()))
}

/// Σ_{i<n} ⌊(a·i + b)/m⌋ for n >= 0, m > 0 (the AtCoder Library's
/// floor_sum, extended to negative a and b).
pub fn floor_sum(n: i128, m: i128, a: i128, b: i128) -> i128 {
    let (mut n, mut m) = (n, m);
    let pairs = n * (n - 1) / 2;
    let (a0, b0) = (a.rem_euclid(m), b.rem_euclid(m));
    let mut ans = pairs * ((a - a0) / m) + n * ((b - b0) / m);
    let (mut a, mut b) = (a0, b0);
    loop {
        if a >= m {
            ans += n * (n - 1) / 2 * (a / m);
            a %= m;
        }
        if b >= m {
            ans += n * (b / m);
            b %= m;
        }
        let y_max = a * n + b;
        if y_max < m {
            return ans;
        }
        (n, b) = (y_max / m, y_max % m);
        (m, a) = (a, m);
    }
}

/// How long a segment runs and where it leaves the NCO's phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SegmentRun {
    /// Clocks from loading the segment to the clock its last step is
    /// commanded, both counted (the next segment loads on the clock after).
    pub clocks: u64,
    /// NCO phase after it.
    pub phase: u32,
}

/// Clocks `seg` takes when the NCO's phase starts at `phase` and the step
/// output never holds the NCO back; `None` if it never completes: the rate
/// would turn direction (pass 0) or leave the i32 range before the last
/// step, or it would take more than [`CLOCK_LIMIT`] clocks
/// ([`JERK_CLOCK_LIMIT`] with a jerk).
///
/// The NCO adds |rate_k| to its 32-bit phase on clock k of the segment and
/// commands a step on every carry; after n advancing clocks it has
/// commanded ⌊(phase + S(n))/2^32⌋ steps, S(n) = Σ|rate_k|. Without a jerk
/// rate_k = ⌊(rate·2^16 + 2^15 + k·accel)/2^16⌋, so S(n) is a floor sum
/// ([`floor_sum`]) while the sign holds, and the least n with S(n) >=
/// steps·2^32 − phase is found by bisection, plus the load clock. With a
/// jerk the rate is followed clock by clock ([`jerk_segment_clocks`]).
pub fn segment_clocks(seg: &Segment, phase: u32) -> Option<SegmentRun> {
    if seg.steps == 0 {
        return Some(SegmentRun { clocks: 1, phase });
    }
    let dir = direction(seg);
    if dir == 0 {
        return None;
    }
    if seg.jerk != 0 {
        return jerk_segment_clocks(seg, phase, dir);
    }
    ramp_segment_clocks(seg, phase, dir)
}

/// [`segment_clocks`] for a segment with steps and no jerk stepping in
/// direction `dir` (±1), in closed form.
pub fn ramp_segment_clocks(seg: &Segment, phase: u32, dir: i64) -> Option<SegmentRun> {
    // Magnitude frame: |rate_k| = ⌊(r0 + c + k·am)/2^16⌋ must stay in
    // 0..=max: forwards c is the load's half LSB; backwards the register
    // is −r0 + 2^15 and |⌊x⌋| = ⌈−x⌉ = ⌊(r0 − 2^15 + 2^16 − 1)/2^16⌋.
    let one = 1i128 << ACCEL_FRAC_BITS;
    let (r0, am) = (
        (i128::from(seg.rate) << ACCEL_FRAC_BITS) * i128::from(dir),
        i128::from(seg.accel) * i128::from(dir),
    );
    let half = i128::from(LOAD_FRACTION);
    let c = if dir > 0 { half } else { one - 1 - half };
    // i32: up to 2^31 − 1 forward, 2^31 backward.
    let max = (1i128 << 31) - i128::from(dir > 0);
    let limit = i128::from(CLOCK_LIMIT);
    let n_max = match am {
        0 => limit,
        am if am > 0 => (((max + 1) * one - r0 - c + am - 1) / am).min(limit),
        am => ((r0 + c) / -am + 1).min(limit),
    };
    let sum = |n: i128| floor_sum(n, one, am, r0 + c);
    let need = (i128::from(seg.steps) << 32) - i128::from(phase);
    if sum(n_max) < need {
        return None;
    }
    // S is nondecreasing on 1..=n_max: every term is >= 0 there.
    let (mut lo, mut hi) = (0i128, n_max);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if sum(mid) >= need {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(SegmentRun {
        clocks: hi as u64 + 1,
        phase: (i128::from(phase) + sum(hi)) as u32,
    })
}

/// [`segment_clocks`] for a segment with a jerk, clock by clock as the
/// move engine runs it (48-bit rate and acceleration, 16 fraction bits
/// each).
pub fn jerk_segment_clocks(seg: &Segment, phase: u32, dir: i64) -> Option<SegmentRun> {
    let mut rate = (i64::from(seg.rate) << ACCEL_FRAC_BITS) + LOAD_FRACTION;
    let mut accel = (i64::from(seg.accel) << ACCEL_FRAC_BITS) + LOAD_FRACTION;
    let top = 1i64 << (31 + ACCEL_FRAC_BITS);
    let mut acc = u64::from(phase);
    let mut steps = 0;
    for clock in 1..=JERK_CLOCK_LIMIT {
        let nco = rate >> ACCEL_FRAC_BITS;
        if nco * dir < 0 {
            return None;
        }
        acc += nco.unsigned_abs();
        if acc >> 32 != 0 {
            acc &= 0xFFFF_FFFF;
            steps += 1;
            if steps == seg.steps {
                return Some(SegmentRun {
                    clocks: clock + 1,
                    phase: acc as u32,
                });
            }
        }
        rate += accel >> ACCEL_FRAC_BITS;
        accel += i64::from(seg.jerk);
        // Leaving the i32 rate (or the 48-bit acceleration) range.
        if rate >= top || rate < -top || accel >= top || accel < -top {
            return None;
        }
    }
    None
}

/// Streams positions in, segments out (one tick behind: a tick's end
/// velocity needs the next position).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SegmentBuilder {
    frac_bits: u32,
    c: u64,
    /// p(k−1), p(k), p(k+1): tick k runs from p(k) to p(k+1).
    prev: i64,
    cur: i64,
    next: Option<i64>,
    tick: u64,
    /// Step-less ticks merged into the pending segment, and its start
    /// velocity (as 2·v, the undivided central difference).
    run_ticks: u64,
    run_start: Option<i128>,
    phase: u32,
    clocks: u64,
    adjusted: u64,
}

impl SegmentBuilder {
    /// Starts at position `start` (at rest), `frac_bits`: 0..=32.
    pub fn new(cfg: SegmentConfig, frac_bits: u32, start: i64) -> Result<Self, SegmentError> {
        cfg.validate()?;
        OutOfRange::check("frac_bits", frac_bits.into(), 0, 32)?;
        Ok(Self {
            frac_bits,
            c: cfg.clocks_per_tick(),
            prev: start,
            cur: start,
            next: None,
            tick: 0,
            run_ticks: 0,
            run_start: None,
            phase: cfg.phase,
            clocks: 0,
            adjusted: 0,
        })
    }

    /// The NCO phase after the segments so far.
    pub fn phase(&self) -> u32 {
        self.phase
    }

    /// Clocks the segments so far take ([`segment_clocks`] summed).
    pub fn clocks(&self) -> u64 {
        self.clocks
    }

    /// Segments whose accel (or rate) was changed so that they complete.
    pub fn adjusted(&self) -> u64 {
        self.adjusted
    }

    /// The next tick's end position; returns the segment of the tick before
    /// it, if that tick (with any step-less ticks before it) has steps.
    pub fn push(&mut self, position: i64) -> Result<Option<Segment>, SegmentError> {
        let Some(next) = self.next else {
            self.next = Some(position);
            return Ok(None);
        };
        let seg = self.tick_done(next, i128::from(position) - i128::from(self.cur))?;
        self.prev = self.cur;
        self.cur = next;
        self.next = Some(position);
        self.tick += 1;
        Ok(seg)
    }

    /// The last tick's segment (the axis rests after the last position).
    pub fn finish(&mut self) -> Result<Option<Segment>, SegmentError> {
        let Some(next) = self.next.take() else {
            return Ok(None);
        };
        self.tick_done(next, i128::from(next) - i128::from(self.cur))
    }

    fn whole(&self, p: i64) -> i64 {
        p >> self.frac_bits
    }

    /// |2v| (a doubled central difference, fixed point) as an NCO rate:
    /// v/C steps per clock × 2^32, rounded.
    fn rate(&self, two_v: i128) -> i128 {
        let den = i128::from(self.c) << (self.frac_bits + 1);
        ((two_v << 32) + den / 2) / den
    }

    /// Tick `self.tick` (cur → next) is over; `end_two_v` is 2v at its end.
    fn tick_done(&mut self, next: i64, end_two_v: i128) -> Result<Option<Segment>, SegmentError> {
        let steps = self.whole(next) - self.whole(self.cur);
        let start_two_v = self
            .run_start
            .unwrap_or(i128::from(next) - i128::from(self.prev));
        if steps == 0 {
            self.run_start = Some(start_two_v);
            self.run_ticks += 1;
            return Ok(None);
        }
        let ticks = self.run_ticks + 1;
        self.run_start = None;
        self.run_ticks = 0;
        let dir = i128::from(steps.signum());
        // Velocities against the direction (a reversal) count as 0.
        let r0 = self.rate((start_two_v * dir).max(0));
        let r1 = self.rate((end_two_v * dir).max(0));
        let fastest = r0.max(r1);
        if fastest > i128::from(RATE_MAX) {
            return Err(SegmentError::TooFast {
                tick: self.tick,
                rate: fastest.min(i128::from(i64::MAX)) as i64,
                max: RATE_MAX,
            });
        }
        let advancing = i128::from(ticks * self.c - 1);
        // The steepest SEG_ACCEL is 2^15 rate LSBs a clock (about 1.9·10^10
        // steps/s² at 50 MHz). A steeper ramp keeps its mean rate, so its
        // steps per tick: the start rate takes half the part of the ramp
        // the clamp cuts off.
        let steepest = i128::from(i32::MAX);
        let want = ((r1 - r0) << ACCEL_FRAC_BITS) / advancing;
        let am = want.clamp(-steepest, steepest);
        let r0 = r0 + (((want - am) * (advancing - 1)) >> (ACCEL_FRAC_BITS + 1));
        let seg = |r: i128, a: i128| Segment {
            steps: steps.unsigned_abs() as u32,
            rate: (r * dir) as i32,
            accel: (a * dir) as i32,
            jerk: 0,
        };
        let mut out = seg(r0, am);
        if segment_clocks(&out, self.phase).is_none() {
            self.adjusted += 1;
            out = self.completing(&seg, r0, am, advancing)?;
        }
        let run = segment_clocks(&out, self.phase).expect("checked by `completing`");
        self.phase = run.phase;
        self.clocks += run.clocks;
        Ok(Some(out))
    }

    /// A segment that completes, for one whose ramp (start magnitude `r0`,
    /// magnitude-frame accel `am`) does not: the largest |accel| toward `am`
    /// that completes, from 0 when r0 > 0 or from 1 when the ramp rises
    /// from 0; else a constant rate covering the steps in `advancing`
    /// clocks.
    fn completing(
        &self,
        seg: &dyn Fn(i128, i128) -> Segment,
        r0: i128,
        am: i128,
        advancing: i128,
    ) -> Result<Segment, SegmentError> {
        let completes = |s: &Segment| segment_clocks(s, self.phase).is_some();
        if r0 > 0 || am > 0 {
            let base = i128::from(r0 == 0);
            if completes(&seg(r0, base)) {
                let (mut ok, mut bad) = (base, am);
                while (bad - ok).abs() > 1 {
                    let mid = ok + (bad - ok) / 2;
                    if completes(&seg(r0, mid)) {
                        ok = mid;
                    } else {
                        bad = mid;
                    }
                }
                return Ok(seg(r0, ok));
            }
        }
        let steps = i128::from(seg(0, 0).steps);
        let need = (steps << 32) - i128::from(self.phase);
        let r = ((need + advancing - 1) / advancing).max(1);
        let out = seg(r.min(i128::from(RATE_MAX)), 0);
        if r > i128::from(RATE_MAX) || !completes(&out) {
            return Err(SegmentError::TooFast {
                tick: self.tick,
                rate: r.min(i128::from(i64::MAX)) as i64,
                max: RATE_MAX,
            });
        }
        Ok(out)
    }
}

/// All segments of a profile; `positions[0]` is the start.
#[cfg(feature = "alloc")]
pub fn segments(
    positions: &[i64],
    frac_bits: u32,
    cfg: SegmentConfig,
) -> Result<alloc::vec::Vec<Segment>, SegmentError> {
    let Some((&start, rest)) = positions.split_first() else {
        SegmentBuilder::new(cfg, frac_bits, 0)?;
        return Ok(alloc::vec::Vec::new());
    };
    let mut b = SegmentBuilder::new(cfg, frac_bits, start)?;
    let mut out = alloc::vec::Vec::new();
    for &p in rest {
        out.extend(b.push(p)?);
    }
    out.extend(b.finish()?);
    Ok(out)
}
