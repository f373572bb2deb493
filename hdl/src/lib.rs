//! rust-hdl descriptions of the motionhdl blocks.
//!
//! One file per block. Every block's Verilog goes out through [`verilog`],
//! which turns rust-hdl's raw output into files that can be read together
//! into one yosys or Quartus project (unique module names, no `$`, sized
//! literals, clocks wired straight to flip-flops).

pub mod ls153;
pub mod pulse_mode_selector;
pub mod verilog;

pub use ls153::Ls153;
pub use pulse_mode_selector::{PulseModeSelector, PulseModeSelectorRegistered};
