//! Bit-accurate reference model of the motionhdl gateware.
//!
//! Pure Rust with no rust-hdl dependency, so firmware and host tools can use it
//! directly. Every HDL block in `motionhdl-hdl` has its twin here; the
//! testbench compares the two. The facts both share (configuration,
//! register map, encodings, timing budgets) come from `motionhdl-spec` and
//! are re-exported here under their old paths.

pub use motionhdl_spec::{config, regmap};
pub mod axis_causes;
pub mod counter;
pub mod digital_io;
pub mod fsmc_bridge;
pub mod isa_bridge;
pub mod ls153;
pub mod ls688;
pub mod machine_inputs;
pub mod motion_controller;
pub mod pulse_generator;
pub mod pulse_mode_selector;
pub mod safety_io;
pub mod servo_dac;

pub use config::{Config, ConfigError, CounterFeatures, IsaRam};
