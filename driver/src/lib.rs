//! The firmware driver for the motionhdl gateware, one implementation for
//! Rust and C firmware (docs/driver.md).
//!
//! `no_std`, no heap, no `unsafe` but the memory-mapped bus. Everything goes
//! through a [`Bus`]: [`Mmio`] for the FPGA mapped at an address (an STM32's
//! FSMC bank), or any other implementation (a host test's fake bus, a
//! simulation's bus model). The register offsets are the generated register
//! module's ([`regs`], `generated/rust/motionhdl_regs.rs`), so the driver is
//! built for one register map and [`Card::check`] refuses a card with
//! another (ID.MAP_HASH). The motion algorithms (S-curve segments, homing)
//! are the firmware crate's; this crate only moves their results over the
//! bus. C firmware links the same code as a static library through
//! [`capi`] and `include/motionhdl_driver.h`.

#![no_std]

// The host build (tests, simulations) links std for its panic handler.
#[cfg(not(target_os = "none"))]
extern crate std;

pub mod bus;
pub mod capi;
pub mod card;
pub mod homing;
pub mod safety;

pub use bus::{Bus, Mmio};
pub use card::{runnable, AxisConfig, AxisSample, Card, Stream, FIFO_DEPTH};
pub use motionhdl_spec::pulse::Segment;
pub use safety::{Causes, Input};

/// The register map the driver is built for: the generated Rust module.
#[allow(dead_code, clippy::all)]
pub mod regs {
    include!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../generated/rust/motionhdl_regs.rs"
    ));
}

/// Why a driver call failed. The C API returns `code()` (negative).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// ID.MAGIC is not "MHDL": no motionhdl card at this address, or the
    /// bus is not set up.
    Magic(u32),
    /// ID.VERSION's major number differs from the one the driver was built for.
    Version(u32),
    /// ID.MAP_HASH differs: the card has another register map (another
    /// configuration) than the driver was built with.
    MapHash(u32),
    /// An axis or channel number, a RAM range or a parameter out of range.
    Argument,
    /// STATUS.OVERFLOW: a segment push found the FIFO full.
    FifoOverflow(u32),
    /// The e-stop input still asks for a stop: the latch cannot be cleared.
    EstopInput,
    /// The card is still halted after CLEAR (the input asked in between).
    StillHalted,
    /// The homing sequence failed.
    Homing(motionhdl_firmware::homing::HomingError),
}

impl Error {
    /// The C API's status code (capi's `MOTIONHDL_ERR_*`).
    pub const fn code(self) -> i32 {
        use motionhdl_firmware::homing::HomingError as H;
        match self {
            Self::Magic(_) => capi::MOTIONHDL_ERR_MAGIC,
            Self::Version(_) => capi::MOTIONHDL_ERR_VERSION,
            Self::MapHash(_) => capi::MOTIONHDL_ERR_MAP_HASH,
            Self::Argument => capi::MOTIONHDL_ERR_ARGUMENT,
            Self::FifoOverflow(_) => capi::MOTIONHDL_ERR_FIFO_OVERFLOW,
            Self::EstopInput => capi::MOTIONHDL_ERR_ESTOP_INPUT,
            Self::StillHalted => capi::MOTIONHDL_ERR_STILL_HALTED,
            Self::Homing(H::NotFound) => capi::MOTIONHDL_ERR_HOME_NOT_FOUND,
            Self::Homing(H::StuckOnSwitch) => capi::MOTIONHDL_ERR_HOME_STUCK,
            Self::Homing(H::Lost) => capi::MOTIONHDL_ERR_HOME_LOST,
            Self::Homing(H::NoIndex) => capi::MOTIONHDL_ERR_HOME_NO_INDEX,
        }
    }
}

/// The number of axes (pulse generators, counter channels) of the map.
pub const AXES: u32 = regs::pulse::ax::LEN as u32;

/// Checks an axis or channel number.
fn axis_index(axis: u32) -> Result<usize, Error> {
    if axis < AXES {
        Ok(axis as usize)
    } else {
        Err(Error::Argument)
    }
}

#[cfg(all(target_os = "none", not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // The driver's own paths do not panic (ranges are checked); an
    // overflow check that fires stops here, where a debugger finds it.
    loop {
        core::hint::spin_loop();
    }
}
