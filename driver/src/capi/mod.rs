//! The C API: the driver as a static library for C firmware. cbindgen
//! writes `include/motionhdl_driver.h` from this file (`cbindgen.toml`).
//!
//! Every function takes the card first and returns a status: 0
//! (`MOTIONHDL_OK`), 1 (`MOTIONHDL_BUSY`: not finished yet, call again) or
//! a negative `MOTIONHDL_ERR_*`. A null pointer is `MOTIONHDL_ERR_ARGUMENT`.

use crate::{regs, Bus, Card, Error, Segment};
use core::ffi::c_void;
use motionhdl_firmware::homing::Homing;

mod calls;
mod plan;
pub use calls::*;
pub use plan::*;

pub const MOTIONHDL_OK: i32 = 0;
/// Still running (homing, a stream with segments left): call again.
pub const MOTIONHDL_BUSY: i32 = 1;
/// ID.MAGIC is not "MHDL": no card, or the bus is not set up.
pub const MOTIONHDL_ERR_MAGIC: i32 = -1;
/// ID.VERSION's major number is not the driver's.
pub const MOTIONHDL_ERR_VERSION: i32 = -2;
/// ID.MAP_HASH is not `motionhdl_driver_map_hash()`: another register map.
pub const MOTIONHDL_ERR_MAP_HASH: i32 = -3;
/// A null pointer, a bad axis or channel, a range or value out of bounds.
pub const MOTIONHDL_ERR_ARGUMENT: i32 = -4;
/// A segment FIFO overflowed: a segment was lost.
pub const MOTIONHDL_ERR_FIFO_OVERFLOW: i32 = -5;
/// The e-stop input still asks for a stop.
pub const MOTIONHDL_ERR_ESTOP_INPUT: i32 = -6;
/// Still halted after clearing the latches.
pub const MOTIONHDL_ERR_STILL_HALTED: i32 = -7;
/// Homing: no switch within the travel.
pub const MOTIONHDL_ERR_HOME_NOT_FOUND: i32 = -8;
/// Homing: backing off did not leave the switch.
pub const MOTIONHDL_ERR_HOME_STUCK: i32 = -9;
/// Homing: the slow search lost the switch.
pub const MOTIONHDL_ERR_HOME_LOST: i32 = -10;
/// Homing: no index pulse after the switch.
pub const MOTIONHDL_ERR_HOME_NO_INDEX: i32 = -11;

/// The ID.MAP_HASH of the register map the library was built for (a card
/// with another is `MOTIONHDL_ERR_MAP_HASH`).
#[no_mangle]
pub extern "C" fn motionhdl_driver_map_hash() -> u32 {
    regs::MAP_HASH
}

/// The axes (and counter channels) of that map.
#[no_mangle]
pub extern "C" fn motionhdl_driver_axes() -> u32 {
    crate::AXES
}

/// How the driver reaches the card: four accessors and their context.
/// `motionhdl_bus_mmio` makes one for a card mapped in memory; a test or a
/// simulation passes its own. Offsets are bytes from the window base.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct MotionhdlBus {
    pub ctx: *mut c_void,
    pub read32: Option<unsafe extern "C" fn(ctx: *mut c_void, offset: u32) -> u32>,
    pub write32: Option<unsafe extern "C" fn(ctx: *mut c_void, offset: u32, value: u32)>,
    pub read16: Option<unsafe extern "C" fn(ctx: *mut c_void, offset: u32) -> u16>,
    pub write16: Option<unsafe extern "C" fn(ctx: *mut c_void, offset: u32, value: u16)>,
}

impl MotionhdlBus {
    fn complete(&self) -> bool {
        self.read32.is_some()
            && self.write32.is_some()
            && self.read16.is_some()
            && self.write16.is_some()
    }
}

// SAFETY (all four): `motionhdl_init` accepted only a complete bus, and
// the C caller promised its accessors are valid with its context.
impl Bus for MotionhdlBus {
    fn read32(&mut self, offset: u32) -> u32 {
        self.read32.map_or(0, |f| unsafe { f(self.ctx, offset) })
    }
    fn write32(&mut self, offset: u32, value: u32) {
        if let Some(f) = self.write32 {
            unsafe { f(self.ctx, offset, value) }
        }
    }
    fn read16(&mut self, offset: u32) -> u16 {
        self.read16.map_or(0, |f| unsafe { f(self.ctx, offset) })
    }
    fn write16(&mut self, offset: u32, value: u16) {
        if let Some(f) = self.write16 {
            unsafe { f(self.ctx, offset, value) }
        }
    }
}

/// One card. Fill it with `motionhdl_init`; keep it for every call.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct MotionhdlCard {
    pub bus: MotionhdlBus,
    /// ID.VERSION as `motionhdl_init` read it.
    pub version: u32,
}

/// A segment of a move (PULSE.AX.SEG_*; docs/pulse_generator.md).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct MotionhdlSegment {
    pub steps: u32,
    pub rate: i32,
    pub accel: i32,
    pub jerk: i32,
}

impl From<Segment> for MotionhdlSegment {
    fn from(s: Segment) -> Self {
        MotionhdlSegment {
            steps: s.steps,
            rate: s.rate,
            accel: s.accel,
            jerk: s.jerk,
        }
    }
}

impl From<MotionhdlSegment> for Segment {
    fn from(s: MotionhdlSegment) -> Self {
        Segment {
            steps: s.steps,
            rate: s.rate,
            accel: s.accel,
            jerk: s.jerk,
        }
    }
}

/// How to home one axis (the firmware crate's `HomingParams`).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct MotionhdlHomingParams {
    /// +1: the switch is in the positive direction; -1: negative.
    pub toward: i32,
    /// Clocks per step of the fast search and the back-off, 2..=2^24.
    pub fast_period: u32,
    /// Clocks per step of the slow and index searches, 2..=2^24.
    pub slow_period: u32,
    /// The longest search in steps, 1..=2^30.
    pub max_travel: u32,
    /// Steps to back off the switch, 1..=max_travel.
    pub backoff: u32,
    /// Nonzero: also find the first index pulse after the switch.
    pub index: u32,
}

/// Where home is.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct MotionhdlHome {
    pub position: i32,
    pub count: i32,
    /// The index count, when `has_index` is nonzero.
    pub index: i32,
    pub has_index: u32,
}

/// The homing sequence's state, for the caller to keep (no heap).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct MotionhdlHoming {
    /// Nonzero once `motionhdl_home_start` accepted the parameters.
    pub started: u32,
    pub storage: [u64; MOTIONHDL_HOMING_WORDS],
}

pub const MOTIONHDL_HOMING_WORDS: usize = 8;
const _: () = assert!(core::mem::size_of::<Homing>() <= 8 * MOTIONHDL_HOMING_WORDS);
const _: () = assert!(core::mem::align_of::<Homing>() <= 8);

pub(crate) fn status(r: Result<(), Error>) -> i32 {
    match r {
        Ok(()) => MOTIONHDL_OK,
        Err(e) => e.code(),
    }
}

/// Runs `f` on the card behind `card`, or ERR_ARGUMENT for a null pointer.
///
/// # Safety
///
/// `card` is null or points to a card `motionhdl_init` filled.
pub(crate) unsafe fn with_card(
    card: *mut MotionhdlCard,
    f: impl FnOnce(&mut Card<MotionhdlBus>) -> i32,
) -> i32 {
    // SAFETY: the caller's contract.
    match unsafe { card.as_ref() } {
        Some(c) => f(&mut Card::new(c.bus)),
        None => MOTIONHDL_ERR_ARGUMENT,
    }
}

/// Runs `f` on the card and stores its value in `*out`.
///
/// # Safety
///
/// As for [`with_card`]; `out` is null or writable.
pub(crate) unsafe fn fetch<T>(
    card: *mut MotionhdlCard,
    out: *mut T,
    f: impl FnOnce(&mut Card<MotionhdlBus>) -> Result<T, Error>,
) -> i32 {
    // SAFETY: the caller's contract.
    let Some(out) = (unsafe { out.as_mut() }) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    let store = |c: &mut Card<MotionhdlBus>| match f(c) {
        Ok(v) => {
            *out = v;
            MOTIONHDL_OK
        }
        Err(e) => e.code(),
    };
    // SAFETY: the caller's contract.
    unsafe { with_card(card, store) }
}

/// Runs `f` on the card with `*input`.
///
/// # Safety
///
/// As for [`with_card`]; `input` is null or valid.
pub(crate) unsafe fn given<T>(
    card: *mut MotionhdlCard,
    input: *const T,
    f: impl FnOnce(&mut Card<MotionhdlBus>, &T) -> Result<(), Error>,
) -> i32 {
    // SAFETY: the caller's contract.
    let Some(input) = (unsafe { input.as_ref() }) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    // SAFETY: the caller's contract.
    unsafe { with_card(card, |c| status(f(c, input))) }
}

unsafe extern "C" fn mmio_read32(ctx: *mut c_void, offset: u32) -> u32 {
    // SAFETY: `motionhdl_bus_mmio`'s contract.
    unsafe { regs::read32(ctx as usize, offset as usize) }
}
unsafe extern "C" fn mmio_write32(ctx: *mut c_void, offset: u32, value: u32) {
    // SAFETY: as above.
    unsafe { regs::write32(ctx as usize, offset as usize, value) }
}
unsafe extern "C" fn mmio_read16(ctx: *mut c_void, offset: u32) -> u16 {
    // SAFETY: as above.
    unsafe { regs::read16(ctx as usize, offset as usize) }
}
unsafe extern "C" fn mmio_write16(ctx: *mut c_void, offset: u32, value: u16) {
    // SAFETY: as above.
    unsafe { regs::write16(ctx as usize, offset as usize, value) }
}

/// The bus of a card mapped at `base` (e.g. 0x60000000, FSMC bank 1
/// region 1), with volatile 32- and 16-bit accesses. The FSMC must be set
/// up (docs/fsmc_bridge.md) before the first call.
#[no_mangle]
pub extern "C" fn motionhdl_bus_mmio(base: usize) -> MotionhdlBus {
    MotionhdlBus {
        ctx: base as *mut c_void,
        read32: Some(mmio_read32),
        write32: Some(mmio_write32),
        read16: Some(mmio_read16),
        write16: Some(mmio_write16),
    }
}

/// Fills `card` and checks the card: ID.MAGIC, ID.VERSION's major,
/// ID.MAP_HASH (`MOTIONHDL_ERR_MAGIC`, `_VERSION`, `_MAP_HASH`).
///
/// # Safety
///
/// `card` is null or writable; `bus`'s accessors are valid with its ctx.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_init(card: *mut MotionhdlCard, bus: MotionhdlBus) -> i32 {
    // SAFETY: the caller's contract.
    let Some(c) = (unsafe { card.as_mut() }) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    if !bus.complete() {
        return MOTIONHDL_ERR_ARGUMENT;
    }
    *c = MotionhdlCard { bus, version: 0 };
    match Card::new(bus).check() {
        Ok(v) => {
            c.version = v;
            MOTIONHDL_OK
        }
        Err(e) => e.code(),
    }
}
