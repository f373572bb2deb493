//! Facts of the ISA address-counter interface (docs/isa_bridge.md) shared
//! by the model, the HDL and the PC side: register numbers, STATUS bits,
//! the card's address decode, and the external-SRAM sequencer's encoding.

/// Register numbers, selected by SA1..SA0 (from the register map).
pub mod reg {
    pub const DATA: u16 = 0;
    pub const ADDR_CLEAR: u16 = 1;
    pub const ADDR_INC: u16 = 2;
    pub const STATUS: u16 = 3;
}

/// STATUS bits.
pub mod status {
    pub const ADDR_MASK: u16 = 0x03ff;
    pub const IRQ_EN: u16 = 1 << 11;
    pub const AUTO_INC: u16 = 1 << 12;
    pub const WRAPPED: u16 = 1 << 13;
    pub const COLLISION: u16 = 1 << 14;
    pub const BELL: u16 = 1 << 15;
}

/// The mailbox words at the top of the shared RAM (from the register map).
pub mod mailbox {
    use crate::regmap::{ISA_MAILBOX_TO_DSP, ISA_MAILBOX_TO_PC};
    /// The DSP side writes it to ring the PC.
    pub const TO_PC: u16 = ISA_MAILBOX_TO_PC as u16;
    /// The PC writes it to ring the DSP side.
    pub const TO_DSP: u16 = ISA_MAILBOX_TO_DSP as u16;
}

/// The card answers at `port` when SA9..SA2 equal the base switches and AEN
/// is low: what the 74LS688 (G̅ = AEN) decides.
pub fn selected(port: u16, aen: bool, base: u8) -> bool {
    !aen && ((port >> 2) & 0xff) as u8 == base
}

/// The I/O port of register `reg` on a card whose switches read `base`.
pub fn port(base: u8, reg: u16) -> u16 {
    (u16::from(base) << 2) | (reg & 3)
}

/// States of the external-SRAM sequencer.
pub mod sram_state {
    pub const READ: u8 = 0;
    pub const SETUP: u8 = 1;
    pub const PULSE1: u8 = 2;
    pub const PULSE2: u8 = 3;
    pub const HOLD: u8 = 4;
}

/// Clocks the read address must be stable before the sampled data is
/// taken: covers an SRAM access time of up to one clock minus the pad
/// delays (35 ns parts at 50 MHz).
pub const SRAM_READ_SETTLE_CLOCKS: u8 = 2;
