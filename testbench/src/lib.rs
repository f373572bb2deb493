//! HDL-vs-model checks, scenario traces and external simulator drivers.
//!
//! Infrastructure:
//! * [`harness`]: stepping rust-hdl blocks directly (no `Simulation`
//!   thread), check reports, the random generator, and the rule for
//!   external tools under CI.
//! * [`tour`]: transition tours through every reachable (state, input).
//! * [`trace`]: our VCD writer (real timescale, port names, scopes by block).
//! * [`verilated`]: a Verilated module stepped from Rust port by port,
//!   for testbenches that react to its outputs every clock.
//! * [`verilog_sim`]: runs Verilog in Icarus Verilog and Verilator, with a
//!   vector testbench written from the design's ports.
//! * [`player`]: replays a bus-functional model's timed pin events through
//!   any design in Icarus or Verilator.
//! * [`netlist`]: the post-synthesis yosys netlist of a generated module.
//! * [`state_map`]: the HDL's register snapshots as the model's state types.
//!
//! Then the bus-functional models ([`bfm`]), the checks ([`checks`], one
//! file or folder per block, named as the block's file in `hdl/src/`), the
//! scenario traces `motionhdl trace` writes ([`scenarios`]), the one list
//! of checks `motionhdl verify` runs ([`registry`]) and the throughput
//! measurements of `motionhdl bench` ([`bench`]).

pub mod bench;
pub mod bfm;
pub mod c_driver;
pub mod checks;
pub mod harness;
pub mod netlist;
pub mod player;
pub mod plot;
pub mod registry;
pub mod scale;
pub mod scenarios;
pub mod servo_loop;
pub mod state_map;
pub mod tour;
pub mod trace;
pub mod verilated;
pub mod verilog_sim;

pub use harness::CheckReport;
