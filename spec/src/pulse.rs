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
/// Words of the segment RAM per slot (steps, rate, accel, one spare); the
/// jerks sit in a ring of their own, twice as deep, so the running
/// segment's jerk stays on that RAM's output while the FIFO fills.
pub const SEGMENT_SLOT_WORDS: usize = 4;

/// Fraction bits below the NCO rate's LSB in the running segment's rate
/// (and so in SEG_ACCEL): one SEG_ACCEL LSB changes the rate by 2^-16 of
/// its LSB per clock, 2^-48 steps/clock², about 8.9 steps/s² at 50 MHz.
pub const ACCEL_FRAC_BITS: u32 = 16;
/// Fraction bits below SEG_ACCEL's LSB in the running segment's
/// acceleration (and so in SEG_JERK): one SEG_JERK LSB changes the
/// acceleration by 2^-16 of its LSB per clock, 2^-64 steps/clock³, about
/// 6 800 steps/s³ at 50 MHz.
pub const JERK_FRAC_BITS: u32 = 16;

/// One segment of a position move. The running segment keeps a rate r and
/// an acceleration a with fraction bits ([`ACCEL_FRAC_BITS`],
/// [`JERK_FRAC_BITS`]): it loads r = `rate`·2^16 + 2^15 and a =
/// `accel`·2^16 + 2^15 (half an LSB, so the floors below round to
/// nearest); on every clock the NCO advances, r += ⌊a / 2^16⌋ and a +=
/// `jerk` (both modulo 2^48), and the NCO runs at ⌊r / 2^16⌋. The segment
/// ends once it has commanded `steps` steps (the sign of the rate is the
/// direction; it should not change within a segment).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Segment {
    pub steps: u32,
    pub rate: i32,
    pub accel: i32,
    pub jerk: i32,
}

/// The fraction a load gives the rate and the acceleration: half an LSB.
pub const LOAD_FRACTION: i64 = 1 << (ACCEL_FRAC_BITS - 1);

/// Bits of the running segment's rate and acceleration registers.
pub const RAMP_BITS: u32 = 32 + ACCEL_FRAC_BITS;
const _: () = assert!(ACCEL_FRAC_BITS == JERK_FRAC_BITS);
