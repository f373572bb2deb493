//! Cycle model of the quadrature/pulse counter bank (docs/counter_bank.md).
//!
//! Every register of the specification is a field of [`ChannelState`] (or of
//! [`Bank`]), and [`Channel::clock`] computes every next value from the
//! values before the edge, exactly as the flip-flops do, so the testbench can
//! compare the model with the HDL every clock and exhaustive checks can put
//! whole states into sets.
//!
//! Addresses, field positions and masks all come from
//! [`regmap::counter_bank`](crate::regmap::counter_bank); nothing here
//! restates a number the map owns.
//!
//! One file per part, as the HDL has them (`hdl/src/input_filter.rs`,
//! `counter_channel.rs`, `counter_bank.rs`): `input_filter` (the
//! synchroniser and digital filter of one pin), `channel` (one channel's
//! counting, error and index logic) and `bank` (the channels behind the
//! register bus).

mod bank;
mod channel;
mod input_filter;
#[cfg(test)]
mod tests;

pub use bank::Bank;
pub use channel::{Channel, ChannelInputs, ChannelState};
pub use input_filter::InputFilter;
pub use motionhdl_spec::bus::{
    mask_bits, sign_extend, wrap, BusCycle, CounterFeatures, CounterParams,
};
