//! The ISA bridge: its four I/O registers on the PC's bus and the MCU's
//! window onto the RAM it shares with the PC (SHARED_RAM).

use super::{field, reg, Access, Block, Memory, MCU_RAM_BYTE_OFFSET};

/// Words in the shared dual-port RAM behind the ISA bridge (2 KB).
pub const ISA_RAM_WORDS: u32 = 1024;
/// Bits of the ISA bridge's address counter.
pub const ISA_ADDR_BITS: u32 = 10;
/// The mailbox word the DSP side writes to ring the PC (STATUS.BELL; the
/// PC's read of it through DATA clears the bell), as the IDT7130's
/// left-port mailbox works.
pub const ISA_MAILBOX_TO_PC: u32 = ISA_RAM_WORDS - 2;
/// The mailbox word the PC writes to ring the DSP side (the MCU's
/// SAFETY.CAUSE.DOORBELL), as the IDT7130's right-port mailbox works.
pub const ISA_MAILBOX_TO_DSP: u32 = ISA_RAM_WORDS - 1;

/// The ISA bridge's four I/O registers, at port offsets 0..=3 from the
/// card's base port (SA1..SA0 select; SA9..SA2 must equal the base).
/// Every access is one 16-bit word on SD15..SD0.
pub fn isa_bridge() -> Block {
    use Access::*;
    let status_fields = || {
        let mut addr = field(
            "ADDR",
            0,
            ISA_ADDR_BITS,
            ReadWrite,
            "Address counter: the RAM word DATA reaches. A write loads it.",
        );
        addr.reset = 0;
        vec![
            addr,
            field(
                "IRQ_EN",
                11,
                1,
                ReadWrite,
                "Drive the card's IRQ line high while BELL is set.",
            ),
            field(
                "AUTO_INC",
                12,
                1,
                ReadWrite,
                "DATA accesses advance the address counter after the access.",
            ),
            field(
                "WRAPPED",
                13,
                1,
                WriteOneToClear,
                "Sticky: the counter wrapped from the last word to 0.",
            ),
            field(
                "COLLISION",
                14,
                1,
                WriteOneToClear,
                "Sticky: the DSP port wrote the word a PC write was waiting to write.",
            ),
            field(
                "BELL",
                15,
                1,
                WriteOneToClear,
                "Doorbell: the DSP side wrote the PC's mailbox word (ISA_MAILBOX_TO_PC). A DATA read of that word clears it too.",
            ),
        ]
    };
    Block {
        name: "ISA",
        description: "ISA address-counter interface to the shared 1 K x 16 dual-port RAM",
        base: 0,
        address_bits: 2,
        registers: vec![
            reg(
                "DATA",
                0,
                ReadWrite,
                "The RAM word at the address counter.",
                "With STATUS.AUTO_INC set, every access advances the counter afterwards.",
                vec![field("VALUE", 0, 16, ReadWrite, "RAM word.")],
            ),
            reg(
                "ADDR_CLEAR",
                1,
                ReadWrite,
                "Clears the address counter and STATUS.WRAPPED.",
                "Any access, read or write, clears; data written is ignored, reads return STATUS as it was before.",
                vec![],
            ),
            reg(
                "ADDR_INC",
                2,
                ReadWrite,
                "Advances the address counter by one.",
                "Any access, read or write, advances; data written is ignored, reads return STATUS as it was before.",
                vec![],
            ),
            reg(
                "STATUS",
                3,
                ReadWrite,
                "Address counter and status.",
                "A write loads ADDR, IRQ_EN and AUTO_INC and clears the sticky bits written as 1.",
                status_fields(),
            ),
        ],
        arrays: vec![],
    }
}

/// The MCU/DSP port of the shared RAM, as a window on the MCU bus (present
/// only with the internal RAM).
pub(super) fn shared_ram() -> Memory {
    Memory {
        name: "SHARED_RAM",
        description: "The MCU/DSP port of the 1 K x 16 RAM shared with the PC (ISA bridge). One word per 16-bit access.",
        byte_offset: MCU_RAM_BYTE_OFFSET,
        words: ISA_RAM_WORDS,
        word_bits: 16,
    }
}
