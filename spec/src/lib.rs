//! The specification layer of motionhdl: facts, never behaviour.
//!
//! The bit-accurate model (`motionhdl-model`), the rust-hdl blocks
//! (`motionhdl-hdl`) and the firmware (`motionhdl-firmware`) all stand on
//! this crate and share only what is here: the build configuration, the
//! register map, the bus cycle and its word arithmetic, the encodings of
//! state the checks compare, the FSMC and ISA timing budgets and the
//! constants of the pulse generators. How a block behaves is written twice,
//! in the model and in the HDL, and the testbench compares the two.

//!
//! Without the default `std` feature only the constants firmware needs
//! ([`pulse`], [`safety_io`], [`servo_dac`]) are built, with `core` alone,
//! so a `no_std` driver for a Cortex-M shares them instead of copying them.

#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "std")]
pub mod bus;
#[cfg(feature = "std")]
pub mod config;
#[cfg(feature = "std")]
pub mod fsmc;
#[cfg(feature = "std")]
pub mod isa;
pub mod pulse;
#[cfg(feature = "std")]
pub mod regmap;
pub mod safety_io;
pub mod servo_dac;

#[cfg(feature = "std")]
pub use config::{Config, ConfigError, CounterFeatures, IsaRam};
