//! Facts of the pulse generators (docs/pulse_generator.md) shared by the
//! model, the HDL and the firmware: register widths, the segment FIFO's
//! depth and what one segment holds.

/// Bits of the pending-step queue (two's complement) in the gateware.
pub const PENDING_BITS: u32 = 16;
/// Bits of the timing registers and of the timers that check them.
pub const TIMER_BITS: u32 = 16;

/// Segments the move FIFO holds, besides the one running. The FIFO is
/// block RAM (256 words of 32 bits per axis, two iCE40 SB_RAM40_4K or one
/// ECP5 DP16KD: four words a slot), so a whole profile fits and the
/// firmware refills rarely; only a copy of the head segment sits in
/// flip-flops.
pub const SEGMENT_FIFO_DEPTH: usize = 64;
/// Words of the segment RAM per slot (steps, rate, accel, one spare).
pub const SEGMENT_SLOT_WORDS: usize = 4;

/// One segment of a position move: the NCO starts at `rate` and adds
/// `accel` to it on every clock it advances, until it has commanded
/// `steps` steps (the sign of the rate is the direction; it should not
/// change within a segment).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Segment {
    pub steps: u32,
    pub rate: i32,
    pub accel: i32,
}
