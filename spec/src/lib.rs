//! The specification layer of motionhdl: facts, never behaviour.
//!
//! The bit-accurate model (`motionhdl-model`), the rust-hdl blocks
//! (`motionhdl-hdl`) and the firmware (`motionhdl-firmware`) all stand on
//! this crate and share only what is here: the build configuration, the
//! register map, the bus cycle and its word arithmetic, the encodings of
//! state the checks compare, the FSMC and ISA timing budgets and the
//! constants of the pulse generators. How a block behaves is written twice,
//! in the model and in the HDL, and the testbench compares the two.

pub mod bus;
pub mod config;
pub mod fsmc;
pub mod isa;
pub mod pulse;
pub mod regmap;
pub mod safety_io;
pub mod servo_dac;

pub use config::{Config, ConfigError, CounterFeatures, IsaRam};
