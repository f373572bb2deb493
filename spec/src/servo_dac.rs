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

/// The serial (SPI) option (SERVO.SERIAL.MODE = 1): one 24-bit frame per
/// channel, MSB first, an 8-bit prefix (SERVO.PREFIX, the part's command
/// and channel address) and the 16-bit code. SDIN changes at SCLK's
/// rising edges and is sampled by the DAC at its falling edges; SCLK
/// idles high; SYNC is low for the frame; one LDAC pulse after the fourth
/// frame updates all four outputs.
pub const FRAME_BITS: u32 = 24;

/// Minimum SCLK high and low times (t2, t3: 20 ns) and SYNC high time
/// between frames (t8: 30 ns), in nanoseconds, from Table 5 of the
/// AD5686R/AD5685R/AD5684R data sheet (Rev. B, 2.7 V <= VLOGIC <= 5.5 V).
/// Table 5 is the part's daisy-chain and readback table, slower than its
/// standalone write (50 MHz SCLK), so these hold in either mode. The same
/// table's SYNC-to-SCLK-fall set-up (t4, 20 ns) is met by the first SCLK
/// high half, SCLK-fall-to-SYNC-rise (t7, 10 ns) by the last low half and
/// a clock, data set-up and hold (t5, t6, 5 ns) by half an SCLK period.
pub const SCLK_HALF_NS: u64 = 20;
pub const SYNC_HIGH_NS: u64 = 30;

/// The AD5686R's frame prefix per channel (its Tables 7 and 8): command
/// 0001, "write to input register n" (the output changes at LDAC), and
/// the one-hot channel address DAC A..D. Other 24-bit quad DACs take
/// their own prefix in SERVO.PREFIX.
pub const AD5686R_PREFIX: [u32; DAC_CHANNELS as usize] = [0x11, 0x12, 0x14, 0x18];

/// [`update_latency`] for the serial option: per channel SYNC high
/// SYNC_HIGH + 1 clocks, 48 SCLK halves of SCLK_HALF + 1 clocks and one
/// clock of SYNC low after the last rise; then SYNC_HIGH + 1 clocks before
/// LDAC falls and LDAC_LOW + 1 clocks low. Zero jitter as the parallel
/// option's.
pub fn serial_update_latency(sclk_half: u32, sync_high: u32, ldac_low: u32) -> u32 {
    let frame = 2 * FRAME_BITS * (sclk_half + 1);
    DAC_CHANNELS * (sync_high + 1 + frame + 1) + sync_high + 1 + ldac_low + 1
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

    #[test]
    fn the_serial_frame_times_in_clocks() {
        // At 50 MHz: SCLK halves of 1 clock (25 MHz), SYNC high 2 clocks.
        assert_eq!(clocks_for_ns(SCLK_HALF_NS, 50_000_000), 1);
        assert_eq!(clocks_for_ns(SYNC_HIGH_NS, 50_000_000), 2);
        // Four frames of 2 + 48 + 1 clocks, a 2-clock gap, LDAC 3 clocks.
        assert_eq!(serial_update_latency(0, 1, 2), 4 * 51 + 2 + 3);
    }
}
