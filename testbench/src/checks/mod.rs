//! The checks of each block, named as the block's file in `hdl/src/`:
//! the rust-hdl block against its model twin, and the generated Verilog
//! (and its netlist) against the same model on the same stimulus.

pub mod counter_bank;
pub mod counter_channel;
pub mod fsmc_bridge;
pub mod input_filter;
pub mod isa_bridge;
pub mod ls153;
pub mod ls688;
pub mod motion_controller;
pub mod move_engine;
pub mod pulse_bank;
pub mod pulse_generator;
pub mod pulse_mode_selector;
pub mod quadrature_core;
pub mod safety_io;
pub mod servo_dac;
