//! Facts of the safety and I/O block (docs/safety_io.md) shared by the
//! model, the HDL and the firmware: the watchdog's key and the block's
//! latencies, which the docs state and the checks hold both twins to.

/// The value a WDT_RELOAD write must carry to reload the watchdog; any
/// other value is ignored, so a runaway loop that writes the register with
/// garbage does not keep the watchdog fed.
pub const WATCHDOG_KEY: u32 = 0x5AFE_D06E;

/// Clock edges from the edge that first samples the e-stop input low to
/// the edge where HALT (and ESTOP, and the ENABLE outputs' drop) take
/// effect: two synchroniser flip-flops, then the latch.
pub const ESTOP_LATENCY: u32 = 3;

/// Clock edges from a cause bit (or its mask, or the polarity) changing to
/// the IRQ pin following it: the pin is one flip-flop after OR(cause AND
/// mask).
pub const IRQ_LATENCY: u32 = 1;
