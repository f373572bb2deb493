//! Bus-functional models: each bus once, in Rust, as timed pin events.
//! rust-hdl checks step through the events directly; the Verilog checks
//! replay the same events through [`crate::player`].

pub mod fsmc;
pub mod isa;
