//! Position moves of one axis: the segment FIFO and the running segment.

use super::{Segment, SEGMENT_FIFO_DEPTH};

/// A field of the segment being written (the SEG_* registers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentField {
    Steps,
    Rate,
    Accel,
}

/// Position moves: a FIFO of segments the MCU streams (e.g. to follow an
/// S-curve) and the segment being run. The SEG_* writes go straight into
/// the FIFO's free tail slot (no staging registers: 96 flip-flops less per
/// axis); while the FIFO is full they are dropped, and a PUSH then
/// overflows. A slot keeps what was last written into it, so fields not
/// written since the slot last held a segment carry that old value.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MoveEngine {
    slots: [Segment; SEGMENT_FIFO_DEPTH],
    head: usize,
    count: usize,
    active: bool,
    rate: i32,
    accel: i32,
    remaining: u32,
    done: bool,
    overflow: bool,
}

impl MoveEngine {
    /// The NCO rate: the running segment's, or 0.
    pub fn rate(&self) -> i32 {
        if self.active {
            self.rate
        } else {
            0
        }
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
    pub fn level(&self) -> usize {
        self.count
    }
    /// (active, rate, remaining, done, overflow, level): the registers the
    /// gateware compares.
    pub fn probe(&self) -> (bool, u32, u32, bool, bool, u32) {
        (
            self.active,
            self.rate as u32,
            self.remaining,
            self.done,
            self.overflow,
            self.count as u32,
        )
    }
    pub fn clear_overflow(&mut self) {
        self.overflow = false;
    }

    /// One edge with a whole segment pushed at once (its three fields
    /// written into the tail slot and pushed in the same edge).
    pub fn clock(&mut self, run: bool, commanded: bool, advancing: bool, push: Option<Segment>) {
        let writes = push.map(|s| {
            [
                (SegmentField::Steps, s.steps),
                (SegmentField::Rate, s.rate as u32),
                (SegmentField::Accel, s.accel as u32),
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
        // The tail slot, from the state before this edge (a pop moves head
        // and count together, so it names the same slot after it).
        let tail = (self.head + self.count) % SEGMENT_FIFO_DEPTH;
        if self.active {
            if commanded {
                self.remaining -= 1;
                if self.remaining == 0 {
                    self.active = false;
                    ended = true;
                }
            }
            if advancing {
                self.rate = self.rate.wrapping_add(self.accel);
            }
        } else if run && self.count > 0 {
            let seg = self.slots[self.head];
            self.head = (self.head + 1) % SEGMENT_FIFO_DEPTH;
            self.count -= 1;
            self.active = seg.steps != 0;
            ended = seg.steps == 0;
            self.rate = seg.rate;
            self.accel = seg.accel;
            self.remaining = seg.steps;
        }
        if ended && self.count == 0 {
            self.done = true;
        }
        if self.count < SEGMENT_FIFO_DEPTH {
            let slot = &mut self.slots[tail];
            for &(field, v) in writes {
                match field {
                    SegmentField::Steps => slot.steps = v,
                    SegmentField::Rate => slot.rate = v as i32,
                    SegmentField::Accel => slot.accel = v as i32,
                }
            }
        }
        if push {
            if self.count < SEGMENT_FIFO_DEPTH {
                self.count += 1;
                self.done = false;
            } else {
                self.overflow = true;
            }
        }
    }
}
