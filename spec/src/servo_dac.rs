//! Facts of the servo DAC block (docs/servo_dac.md) shared by the model,
//! the HDL and the firmware: the DAC7744-style interface's channel count,
//! safe code and write sequence, and the servo tick's timing.

/// DAC channels: the DAC7744 has four (A..D), addressed by A1:A0.
pub const DAC_CHANNELS: u32 = 4;

/// The code every channel is driven to on reset, on an e-stop and on a
/// watchdog bite: mid-scale, 0 V in the DAC7744's bipolar ±10 V range
/// (straight binary: 0x0000 = −10 V, 0xFFFF = +10 V − 1 LSB).
pub const SAFE_CODE: u32 = 0x8000;

/// Minimum CS low time of a write (t_WCS) and minimum LOADDACS low time
/// (t_LWD), in nanoseconds: 50 ns each in Table II of the DAC7624/DAC7625
/// data sheet (Burr-Brown, the DAC7744's 12-bit sibling with the same
/// parallel interface and timing table layout; the DAC7744's own Table II
/// was not in the sources searched, so check it against your data sheet
/// and raise TIMING if it asks for more). Address, data and R/W need 0 ns
/// of setup before CS falls and 0 ns of hold after it rises (t_AS, t_DS,
/// t_WS, t_AH, t_DH, t_WH); the block gives each a whole clock.
pub const CS_LOW_NS: u64 = 50;
pub const LDAC_LOW_NS: u64 = 50;

/// Clocks per channel write besides CS's low time: one clock of address
/// and data setup with CS high, one clock of hold with CS high after it.
pub const WRITE_OVERHEAD_CLOCKS: u32 = 2;

/// The smallest whole number of clocks that lasts at least `ns`
/// nanoseconds at `clock_hz`, at least 1.
pub fn clocks_for_ns(ns: u64, clock_hz: u64) -> u32 {
    ((ns * clock_hz).div_ceil(1_000_000_000)).max(1) as u32
}

/// Clock edges from the edge that starts a transfer (the tick's, an
/// UPDATE write's) to the edge where LOADDACS rises and all four DAC
/// outputs change together, for TIMING.CS_LOW = `cs_low` and
/// TIMING.LDAC_LOW = `ldac_low` (CS is low CS_LOW + 1 clocks, LOADDACS
/// LDAC_LOW + 1 clocks). It depends on nothing else: the servo tick's
/// jitter at the DAC outputs is zero clocks.
pub fn update_latency(cs_low: u32, ldac_low: u32) -> u32 {
    DAC_CHANNELS * (cs_low + 1 + WRITE_OVERHEAD_CLOCKS) + ldac_low + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_data_sheet_times_in_clocks() {
        // 50 ns at 50 MHz is 2.5 clocks: 3. At 20 MHz exactly 1.
        assert_eq!(clocks_for_ns(CS_LOW_NS, 50_000_000), 3);
        assert_eq!(clocks_for_ns(CS_LOW_NS, 20_000_000), 1);
        assert_eq!(clocks_for_ns(CS_LOW_NS, 1_000_000), 1);
        // Four writes of 3 + 2 clocks, then LOADDACS low 3 clocks.
        assert_eq!(update_latency(2, 2), 4 * 5 + 3);
    }
}
