//! Position moves of one axis: the segment FIFO in block RAM, the copy of
//! its head segment, and the running segment.

use super::{Segment, SEGMENT_FIFO_DEPTH};
use motionhdl_spec::pulse::{ACCEL_FRAC_BITS, LOAD_FRACTION, RAMP_BITS};

/// A field of the segment being written (the SEG_* registers), in the
/// order the RAM holds them: a slot is four words, field `k` at word `k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentField {
    Steps,
    Rate,
    Accel,
    Jerk,
}

/// Clocks from the moment the head slot holds a segment to the moment its
/// copy can load: one read per field, each one clock behind its address.
pub const SEGMENT_FETCH_CLOCKS: usize = 4;

/// What the move engine's registers hold, as the gateware compares them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveEngineProbe {
    pub active: bool,
    /// The running rate and acceleration, with their fraction bits
    /// (48 bits each), and the jerk.
    pub rate: u64,
    pub accel: u64,
    pub jerk: u32,
    pub remaining: u32,
    pub done: bool,
    pub overflow: bool,
    pub level: u32,
    /// The head segment's copy is complete.
    pub staged: bool,
    /// Fields of the head segment read so far (0 = no read under way).
    pub fetch: u32,
    /// A decelerating stop is under way.
    pub braking: bool,
}

/// Position moves: a ring of `SEGMENT_FIFO_DEPTH` segment slots the MCU
/// streams (e.g. to follow an S-curve), a copy of the head slot read out of
/// the RAM ahead of time, and the segment being run. The SEG_* writes go
/// straight into the free tail slot; while the FIFO is full they are
/// dropped, and a PUSH then overflows. A slot is block RAM: it keeps what
/// was last written into it, across resets too, so fields not written since
/// the slot last held a segment carry that old value.
///
/// SEG_JERK goes into a ring of its own, twice as deep (the tail then never
/// reaches the running segment's jerk): entry (head + level) mod 128, where
/// head counts loads mod 128, so a jerk not written is the one written two
/// laps of the FIFO before, not the slot's.
///
/// The copy: once the head slot holds a segment and no copy is under way,
/// its three fields are read in three clocks (each one clock behind its
/// address), so the copy is complete `SEGMENT_FETCH_CLOCKS` clocks after
/// the push (or the pop) that made the slot the head. A segment loads from
/// the copy; so segments that run at least that long follow each other
/// without a gap, and a shorter one leaves the NCO at rate 0 until the next
/// copy is complete.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MoveEngine {
    slots: Vec<Segment>,
    jerks: Vec<i32>,
    /// Loads, mod 2·SEGMENT_FIFO_DEPTH (the slot is this mod the depth).
    head: usize,
    count: usize,
    staged: Option<Segment>,
    fetch: usize,
    fetched: Segment,
    active: bool,
    /// Rate and acceleration with their fraction bits, sign-extended from
    /// RAMP_BITS.
    rate: i64,
    accel: i64,
    jerk: i32,
    remaining: u32,
    done: bool,
    overflow: bool,
    /// A decelerating stop: `rate` falls by `accel` (against the rate's
    /// sign) on every advancing clock while it still heads the way it
    /// started.
    braking: bool,
}

impl Default for MoveEngine {
    fn default() -> Self {
        Self {
            slots: vec![Segment::default(); SEGMENT_FIFO_DEPTH],
            jerks: vec![0; JERK_RING],
            head: 0,
            count: 0,
            staged: None,
            fetch: 0,
            fetched: Segment::default(),
            active: false,
            rate: 0,
            accel: 0,
            jerk: 0,
            remaining: 0,
            done: false,
            overflow: false,
            braking: false,
        }
    }
}

impl MoveEngine {
    /// The NCO rate: the running segment's, the braking rate while it
    /// still heads the way the stop started, or 0.
    pub fn rate(&self) -> i32 {
        if self.active || self.brake_heading() {
            (self.rate >> ACCEL_FRAC_BITS) as i32
        } else {
            0
        }
    }
    /// Braking, and the rate's whole part still nonzero and of the sign
    /// opposite to the braking acceleration's.
    fn brake_heading(&self) -> bool {
        let whole = self.rate >> ACCEL_FRAC_BITS;
        self.braking && whole != 0 && (whole < 0) != (self.accel < 0)
    }
    /// A decelerating stop is under way (STATUS.BRAKING).
    pub fn braking(&self) -> bool {
        self.braking
    }
    pub fn active(&self) -> bool {
        self.active
    }
    /// Sticky: every pushed segment has commanded all its steps (cleared
    /// by the next push).
    pub fn done(&self) -> bool {
        self.done
    }
    /// Sticky: a push found the FIFO full and was dropped (cleared by a
    /// CTRL write).
    pub fn overflow(&self) -> bool {
        self.overflow
    }
    /// Segments pushed and not yet loaded (0..=SEGMENT_FIFO_DEPTH).
    pub fn level(&self) -> usize {
        self.count
    }
    /// The registers the gateware compares.
    pub fn probe(&self) -> MoveEngineProbe {
        MoveEngineProbe {
            active: self.active,
            rate: self.rate as u64 & RAMP_MASK,
            accel: self.accel as u64 & RAMP_MASK,
            jerk: if self.active { self.jerk as u32 } else { 0 },
            remaining: self.remaining,
            done: self.done,
            overflow: self.overflow,
            level: self.count as u32,
            staged: self.staged.is_some(),
            fetch: self.fetch as u32,
            braking: self.braking,
        }
    }
    pub fn clear_overflow(&mut self) {
        self.overflow = false;
    }

    /// Synchronous reset: every register clears; the slots (block RAM)
    /// keep their contents.
    pub fn reset(&mut self) {
        let slots = std::mem::take(&mut self.slots);
        let jerks = std::mem::take(&mut self.jerks);
        *self = Self {
            slots,
            jerks,
            ..Self::default()
        };
    }

    /// One edge with a whole segment pushed at once (its four fields
    /// written into the tail slot and pushed in the same edge; the
    /// gateware's bus writes one field a clock).
    pub fn clock(&mut self, run: bool, commanded: bool, advancing: bool, push: Option<Segment>) {
        let writes = push.map(|s| {
            [
                (SegmentField::Steps, s.steps),
                (SegmentField::Rate, s.rate as u32),
                (SegmentField::Accel, s.accel as u32),
                (SegmentField::Jerk, s.jerk as u32),
            ]
        });
        self.clock_bus(
            run,
            commanded,
            advancing,
            writes.as_ref().map_or(&[][..], |w| &w[..]),
            push.is_some(),
        );
    }

    /// One edge. `run`: the axis's RUN bit; `commanded`: the NCO commanded
    /// a step this clock; `advancing`: the NCO's phase advanced; `writes`:
    /// SEG_* fields written this clock; `push`: SEG_PUSH written.
    pub fn clock_bus(
        &mut self,
        run: bool,
        commanded: bool,
        advancing: bool,
        writes: &[(SegmentField, u32)],
        push: bool,
    ) {
        let mut ended = false;
        let mut popped = false;
        // The tail slot, from the state before this edge (a pop moves head
        // and count together, so it names the same slot after it).
        let tail = (self.head + self.count) % JERK_RING;
        // A segment loads from the copy as it was before this edge.
        let staged = self.staged;
        let brake_heading = self.brake_heading();
        self.advance_fetch();
        if self.active {
            if commanded {
                self.remaining -= 1;
                if self.remaining == 0 {
                    self.active = false;
                    ended = true;
                }
            }
            if advancing {
                self.advance_rate();
                self.accel = ramp(self.accel + i64::from(self.jerk));
            }
        } else if let Some(seg) = staged.filter(|_| run && !self.braking) {
            popped = true;
            self.staged = None;
            self.active = seg.steps != 0;
            ended = seg.steps == 0;
            self.load_ramp(seg.rate, seg.accel);
            self.jerk = self.jerks[self.head];
            self.remaining = seg.steps;
        }
        if self.braking {
            if advancing {
                self.advance_rate();
            }
            self.braking = brake_heading;
        }
        let count_after_pop = self.count - usize::from(popped);
        if popped {
            self.head = (self.head + 1) % JERK_RING;
        }
        if ended && count_after_pop == 0 {
            self.done = true;
        }
        if count_after_pop < SEGMENT_FIFO_DEPTH {
            let slot = &mut self.slots[tail % SEGMENT_FIFO_DEPTH];
            for &(field, v) in writes {
                match field {
                    SegmentField::Steps => slot.steps = v,
                    SegmentField::Rate => slot.rate = v as i32,
                    SegmentField::Accel => slot.accel = v as i32,
                    SegmentField::Jerk => self.jerks[tail] = v as i32,
                }
            }
        }
        self.count = count_after_pop;
        if push {
            if count_after_pop < SEGMENT_FIFO_DEPTH {
                self.count += 1;
                self.done = false;
            } else {
                self.overflow = true;
            }
        }
    }

    /// Drops the running segment and every queued one, at the edge just
    /// clocked (the safety block's HALT): the FIFO empties, DONE clears;
    /// the slots, the head and OVERFLOW stay.
    pub fn flush(&mut self) {
        self.drop_segments();
        self.braking = false;
    }

    /// A decelerating stop at the edge just clocked, `was_braking` the
    /// state before it: the FIFO empties as at [`Self::flush`], and unless
    /// it was braking already, braking starts from `rate` (the NCO's rate
    /// in the clock before the edge) with SEG_ACCEL = ∓`decel` (against
    /// the rate's sign), loaded as a segment's fields load.
    pub fn brake(&mut self, was_braking: bool, rate: i32, decel: u32) {
        self.drop_segments();
        if !was_braking {
            let decel = decel as i32;
            let accel = if rate < 0 {
                decel
            } else {
                decel.wrapping_neg()
            };
            self.braking = true;
            self.load_ramp(rate, accel);
        }
    }

    /// Rate and acceleration as a segment's fields load: 16 fraction bits,
    /// half an LSB added.
    fn load_ramp(&mut self, rate: i32, accel: i32) {
        self.rate = (i64::from(rate) << ACCEL_FRAC_BITS) + LOAD_FRACTION;
        self.accel = (i64::from(accel) << ACCEL_FRAC_BITS) + LOAD_FRACTION;
    }

    /// One advancing clock of the rate: it takes the acceleration's whole
    /// part.
    fn advance_rate(&mut self) {
        self.rate = ramp(self.rate + (self.accel >> ACCEL_FRAC_BITS));
    }

    fn drop_segments(&mut self) {
        self.active = false;
        self.remaining = 0;
        self.count = 0;
        self.staged = None;
        self.fetch = 0;
        self.done = false;
    }

    /// The head slot's copy, one field a clock, from the state before the
    /// edge: a read under way takes the field its address named last clock.
    fn advance_fetch(&mut self) {
        let slot = self.slots[self.head % SEGMENT_FIFO_DEPTH];
        match self.fetch {
            0 if self.staged.is_none() && self.count > 0 => self.fetch = 1,
            0 => {}
            1 => {
                self.fetched.steps = slot.steps;
                self.fetch = 2;
            }
            2 => {
                self.fetched.rate = slot.rate;
                self.fetch = 3;
            }
            _ => {
                self.fetched.accel = slot.accel;
                self.staged = Some(self.fetched);
                self.fetch = 0;
            }
        }
    }
}

const RAMP_MASK: u64 = (1 << RAMP_BITS) - 1;
/// Entries of the jerk ring.
const JERK_RING: usize = 2 * SEGMENT_FIFO_DEPTH;

/// `x` modulo 2^RAMP_BITS, sign-extended: the 48-bit registers wrap.
fn ramp(x: i64) -> i64 {
    let shift = 64 - RAMP_BITS;
    (x << shift) >> shift
}
