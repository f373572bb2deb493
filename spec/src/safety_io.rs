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

/// The machine inputs per axis, in the order the registers and the
/// firmware index them.
pub const MACHINE_INPUTS: [&str; 4] = ["LIMIT_POS", "LIMIT_NEG", "HOME", "ALARM"];

/// Ticks of the filter's prescaler at which a machine input must read a new
/// level in a row before the filtered level takes it (a tick where it reads
/// the old level again starts the count over).
pub const FILTER_TICKS: u32 = 4;

/// Bits of the filter's prescaler: enough for the longest filter time at
/// the fastest clock (50 ms at 400 MHz is a tick every 5 000 000 clocks).
pub const FILTER_PRESCALER_BITS: u32 = 24;

/// Filter times the configuration accepts (`input_filter_us`), in
/// microseconds: from a noisy optical switch to a bouncing mechanical one.
pub const INPUT_FILTER_US: core::ops::RangeInclusive<u64> = 1..=50_000;

/// The built-in filter time: 1 ms covers the bounce of the mechanical
/// limit and home switches machines use.
pub const DEFAULT_INPUT_FILTER_US: u64 = 1_000;

/// The filter's tick period P in clocks for a filter time of `us`
/// microseconds at `clock_hz`: the smallest P with FILTER_TICKS × P clocks
/// at least the filter time. A level held FILTER_TICKS × P clocks always
/// passes; one held fewer than (FILTER_TICKS − 1) × P + 1 never does.
pub fn filter_tick_clocks(us: u64, clock_hz: u64) -> u32 {
    let clocks = (us * clock_hz).div_ceil(1_000_000);
    let p = clocks.div_ceil(u64::from(FILTER_TICKS)).max(1);
    assert!(
        p < 1 << FILTER_PRESCALER_BITS,
        "filter tick of {p} clocks does not fit the prescaler"
    );
    p as u32
}

/// Clock edges from the edge where a filtered limit (or alarm) level turns
/// active to the edge from which the axis starts no step in the stopped
/// direction: the cause flip-flop, then the generator's halt. The filtered
/// level itself follows the pin by two synchroniser edges and the filter.
pub const LIMIT_LATENCY: u32 = 2;

/// Clock edges from the edge where an axis's POSITION reaches an enabled
/// soft limit (SOFT_MAX or SOFT_MIN) to the edge from which it starts no
/// step past it: the pulse bank's comparison flip-flop, then
/// [`LIMIT_LATENCY`].
pub const SOFT_LIMIT_LATENCY: u32 = 1 + LIMIT_LATENCY;

/// General-purpose inputs of the block (the seed's keys and switches):
/// filtered like the machine inputs, with edge events.
pub const GPIO_INPUTS: u32 = 16;

/// General-purpose outputs, each push-pull or open-drain, with a safe
/// state taken on an e-stop or a watchdog bite.
pub const GPIO_OUTPUTS: u32 = 16;

/// Which registers a pair of causes has and how its inputs set them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct CauseKind {
    /// The enable register, if any (without one every cause acts).
    pub ctrl: Option<&'static str>,
    pub cause: &'static str,
    pub mask: &'static str,
    /// A cause sets on its input's rise (else while the input is high).
    pub on_rise: bool,
    /// The causes stop the axis: the first one up, the second one down.
    pub stops: bool,
}

/// The soft limits: SOFT_LIMIT_CTRL/CAUSE/MASK, MAX low, MIN high; levels.
pub const SOFT_LIMITS: CauseKind = CauseKind {
    ctrl: Some("SOFT_LIMIT_CTRL"),
    cause: "SOFT_LIMIT_CAUSE",
    mask: "SOFT_LIMIT_MASK",
    on_rise: false,
    stops: true,
};

/// The counter events: COUNTER_CAUSE/MASK, ERR low, INDEX high; rises.
pub const COUNTER_EVENTS: CauseKind = CauseKind {
    ctrl: None,
    cause: "COUNTER_CAUSE",
    mask: "COUNTER_MASK",
    on_rise: true,
    stops: false,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filter_tick_covers_the_filter_time() {
        // 1 ms at 50 MHz: 50 000 clocks, four ticks of 12 500.
        assert_eq!(filter_tick_clocks(1_000, 50_000_000), 12_500);
        // 1 µs at 1 MHz: one clock, rounded up to a tick of one clock.
        assert_eq!(filter_tick_clocks(1, 1_000_000), 1);
        // 1 µs at 50 MHz: 50 clocks, ticks of 13 (52 clocks).
        assert_eq!(filter_tick_clocks(1, 50_000_000), 13);
        let longest = filter_tick_clocks(*INPUT_FILTER_US.end(), 400_000_000);
        assert_eq!(longest, 5_000_000);
        assert!(longest < 1 << FILTER_PRESCALER_BITS);
    }
}
