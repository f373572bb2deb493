//! The serial DAC option's board (docs/servo_dac.md, "Serial option"): an
//! AD5686R-style quad DAC on the SPI pins, behind an output stage that
//! gives the same ±10 V as the DAC7744 for the same offset-binary code.
//! Its data sheet's behaviour: SDIN is shifted in at SCLK's falls while
//! SYNC is low; at SYNC's rise a 24-bit frame acts (command 0001 writes
//! the input registers its one-hot address bits select, 0011 writes and
//! updates them; any other frame or length is ignored); LDAC's fall moves
//! every input register to its output.

use super::plant::code_volts;
use motionhdl_model::motion_controller::TopOutputs;
use motionhdl_model::servo_dac::SAFE_CODE;

/// The DAC's state, as its pins drive it.
#[derive(Clone, Copy, Debug)]
pub struct SerialDac {
    input: [u16; 4],
    /// The codes the four outputs hold.
    pub output: [u16; 4],
    shift: u32,
    bits: u32,
    /// Frames that acted (24 bits, a write command).
    pub frames: u64,
    /// Frames SYNC ended at another length.
    pub bad_frames: u64,
    /// (SCLK, SYNC, LDAC) of the last clock.
    last: (bool, bool, bool),
}

impl Default for SerialDac {
    fn default() -> Self {
        // RSTSEL high: mid-scale (0 V) from power-up.
        Self {
            input: [SAFE_CODE as u16; 4],
            output: [SAFE_CODE as u16; 4],
            shift: 0,
            bits: 0,
            frames: 0,
            bad_frames: 0,
            last: (true, true, true),
        }
    }
}

impl SerialDac {
    /// The pins after an edge.
    pub fn observe(&mut self, o: &TopOutputs) {
        let (sclk, sync_n, ldac_n) = self.last;
        if sync_n && !o.dac_sync_n {
            (self.shift, self.bits) = (0, 0);
        }
        if !o.dac_sync_n && sclk && !o.dac_sclk {
            self.shift = self.shift << 1 | u32::from(o.dac_sdin);
            self.bits += 1;
        }
        if !sync_n && o.dac_sync_n {
            self.frame();
        }
        if ldac_n && !o.dac_ldac_n {
            self.output = self.input;
        }
        self.last = (o.dac_sclk, o.dac_sync_n, o.dac_ldac_n);
    }

    fn frame(&mut self) {
        let (command, address) = (self.shift >> 20 & 0xf, self.shift >> 16 & 0xf);
        if self.bits != 24 || !matches!(command, 1 | 3) {
            self.bad_frames += 1;
            return;
        }
        self.frames += 1;
        for c in (0..4).filter(|c| address >> c & 1 == 1) {
            self.input[c] = self.shift as u16;
            if command == 3 {
                self.output[c] = self.input[c];
            }
        }
    }

    /// Output `channel`'s voltage.
    pub fn volts(&self, channel: usize) -> f64 {
        code_volts(self.output[channel])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pins of one frame of `word`, then LDAC, as the block drives them.
    fn send(d: &mut SerialDac, word: u32) {
        let mut o = TopOutputs {
            dac_sclk: true,
            dac_sync_n: true,
            dac_ldac_n: true,
            ..Default::default()
        };
        d.observe(&o);
        o.dac_sync_n = false;
        for bit in (0..24).rev() {
            o.dac_sdin = word >> bit & 1 == 1;
            o.dac_sclk = true;
            d.observe(&o);
            o.dac_sclk = false;
            d.observe(&o);
        }
        o.dac_sclk = true;
        d.observe(&o);
        o.dac_sync_n = true;
        d.observe(&o);
    }

    #[test]
    fn a_write_waits_for_ldac_and_a_bad_frame_is_ignored() {
        let mut d = SerialDac::default();
        send(&mut d, 0x12_1234);
        assert_eq!((d.input[1], d.output[1], d.frames), (0x1234, 0x8000, 1));
        let mut o = TopOutputs {
            dac_sclk: true,
            dac_sync_n: true,
            ..Default::default()
        };
        d.observe(&o);
        o.dac_ldac_n = true;
        d.observe(&o);
        assert_eq!(d.output, [0x8000, 0x1234, 0x8000, 0x8000]);
        send(&mut d, 0x61_0000);
        assert_eq!((d.bad_frames, d.input[0]), (1, 0x8000));
    }
}
