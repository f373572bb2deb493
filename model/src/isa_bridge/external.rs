//! The cycle model of `isa_bridge` built for an external dual-port SRAM.

use super::{IsaCoreModel, IsaPins, RamFeedback};
use motionhdl_spec::isa::{sram_state, SRAM_READ_SETTLE_CLOCKS};

/// The pins between the FPGA and an external dual-port SRAM's left port.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SramPins {
    pub addr: u16,
    pub d_out: u16,
    /// The FPGA drives the data pins.
    pub d_oe: bool,
    pub ce_n: bool,
    pub oe_n: bool,
    pub we_n: bool,
}

/// Cycle-accurate model of `isa_bridge` built for an external dual-port
/// SRAM (IDT7025-style, the DSP on its other port): the bus core and the
/// sequencer driving the left port. Reads: CE#/OE# low, the address is the
/// counter, the data pins are sampled every clock and taken once the
/// address has been stable [`SRAM_READ_SETTLE_CLOCKS`]. A queued PC write:
/// one clock of address/data set-up with OE# high, WE# low for two clocks,
/// one clock of hold, all from flops.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct IsaBridgeExternalModel {
    core: IsaCoreModel,
    state: u8,
    pins: SramPins,
    sample: u16,
    stable: u8,
}

impl IsaBridgeExternalModel {
    pub fn new() -> Self {
        Self {
            pins: SramPins {
                ce_n: false,
                oe_n: false,
                we_n: true,
                ..Default::default()
            },
            ..Default::default()
        }
    }
    pub fn core(&self) -> &IsaCoreModel {
        &self.core
    }
    pub fn counter(&self) -> u16 {
        self.core.counter()
    }
    /// The SRAM pins now (all from flops).
    pub fn sram(&self) -> SramPins {
        self.pins
    }
    /// The bus outputs: (sd_out, sd_oe, iocs16_n).
    pub fn outputs(&self, pins: &IsaPins) -> (u16, bool, bool) {
        self.core.outputs(pins)
    }
    /// The ISA IRQ line: never set here, as the FPGA cannot see the DSP.
    pub fn irq(&self) -> bool {
        self.core.irq()
    }
    /// The PC's write of the DSP mailbox word ends in the SRAM this clock.
    pub fn bell_to_dsp(&self) -> bool {
        self.core.bell_to_dsp(&self.feedback())
    }

    fn feedback(&self) -> RamFeedback {
        RamFeedback {
            word: self.sample,
            word_valid: self.takes_sample(),
            write_done: self.state == sram_state::HOLD,
            // The DSP sits on the SRAM's other port, out of sight.
            collision: false,
            dsp_rang: false,
        }
    }

    /// The prefetch takes the data sampled at the previous edge at the next
    /// edge.
    pub fn takes_sample(&self) -> bool {
        self.state == sram_state::READ
            && self.stable >= SRAM_READ_SETTLE_CLOCKS
            && self.core.queued_write().is_none()
    }

    /// One rising edge; `ram_d_in` is what the data pins show at it.
    pub fn clock(&mut self, pins: &IsaPins, reset: bool, ram_d_in: u16) {
        use sram_state::*;
        let s = self.clone();
        let queued = s.core.queued_write();
        let feedback = s.feedback();
        // The read address is the counter as it was before this edge.
        let read_addr = s.core.counter();
        self.core.clock(pins, reset, &feedback);
        self.sample = ram_d_in;
        let mut next = s.pins;
        let state = match s.state {
            READ if queued.is_some() => SETUP,
            READ => READ,
            SETUP => PULSE1,
            PULSE1 => PULSE2,
            PULSE2 => HOLD,
            _ => READ,
        };
        match state {
            READ => {
                next = SramPins {
                    addr: read_addr,
                    d_out: s.pins.d_out,
                    d_oe: false,
                    ce_n: false,
                    oe_n: false,
                    we_n: true,
                };
            }
            SETUP => {
                let (a, d) = queued.expect("a queued write");
                next = SramPins {
                    addr: a,
                    d_out: d,
                    d_oe: true,
                    ce_n: false,
                    oe_n: true,
                    we_n: true,
                };
            }
            PULSE1 | PULSE2 => next.we_n = false,
            _ => next.we_n = true,
        }
        // Count clocks the read address has been on the pins.
        self.stable = if state == READ && s.state == READ && next.addr == s.pins.addr {
            s.stable.saturating_add(1).min(SRAM_READ_SETTLE_CLOCKS)
        } else {
            0
        };
        self.state = state;
        self.pins = next;
        if reset {
            self.state = READ;
            self.stable = 0;
            self.pins.d_oe = false;
            self.pins.we_n = true;
            self.pins.oe_n = false;
            self.pins.ce_n = false;
        }
    }
}
