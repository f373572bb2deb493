//! HDL-vs-model checks, scenario traces and external simulator drivers.
//!
//! * [`harness`]: stepping rust-hdl blocks directly (no `Simulation` thread),
//!   check reports, and the rule for external tools under CI.
//! * [`selector`]: exhaustive checks of the 74LS153 and the pulse-mode selector.
//! * [`verilog_sim`]: runs the generated Verilog in Icarus Verilog and Verilator.
//! * [`netlist`]: the post-synthesis yosys netlist of a generated module.
//! * [`trace`]: our VCD writer (real timescale, port names, scopes by block).
//! * [`scenarios`]: the named traces `motionhdl trace` writes.

pub mod bench;
pub mod bfm;
pub mod counter;
pub mod counter_scenarios;
pub mod counter_stimulus;
pub mod fsmc_bridge;
pub mod harness;
pub mod isa_bridge;
pub mod ls688;
pub mod motion_controller;
pub mod netlist;
pub mod player;
pub mod pulse_bank;
pub mod pulse_generator;
pub mod pulse_scenarios;
pub mod quadrature_core;
pub mod registry;
pub mod scenarios;
pub mod selector;
pub mod state_map;
pub mod system;
pub mod top_model;
pub mod top_stimulus;
pub mod tour;
pub mod trace;
pub mod verilog_sim;

pub use harness::CheckReport;
