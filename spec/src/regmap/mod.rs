//! The register map: the one source of truth for every address, field
//! position, access type and reset value. The HDL address decoders, the
//! model and every export (C headers, SVD, documentation) read it from here.
//!
//! Addresses are word addresses on the internal 32-bit register bus.
//!
//! Each block of the map is built in a file of its own: `id` (ID),
//! `counter_bank` (COUNTER), `pulse_bank` (PULSE) and `isa_bridge` (the
//! ISA bridge's registers and the SHARED_RAM window). This file holds the
//! types they are written in and assembles the MCU's map from them.

mod counter_bank;
mod id;
mod isa_bridge;
mod pulse_bank;
mod safety_io;
mod servo_dac;
#[cfg(test)]
mod tests;

pub use counter_bank::{counter_bank, counter_bank_with, mode, ERR_COUNT_BITS};
pub use id::{gateware_version, id_block, ID_MAGIC};
pub use isa_bridge::{
    isa_bridge, ISA_ADDR_BITS, ISA_MAILBOX_TO_DSP, ISA_MAILBOX_TO_PC, ISA_RAM_WORDS,
};
pub use pulse_bank::pulse_bank;
pub use safety_io::safety_io;
pub use servo_dac::servo_dac;

/// Access type of a register or field, as firmware sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Read-only: writes are ignored.
    ReadOnly,
    /// Write-only: reads return 0.
    WriteOnly,
    /// Read-write.
    ReadWrite,
    /// Reads the value; writing 1 clears the bit, writing 0 leaves it.
    WriteOneToClear,
}

/// One named value of an enumerated field.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EnumValue {
    pub name: &'static str,
    pub value: u32,
    pub description: &'static str,
}

/// A bit field inside a register.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub lsb: u32,
    pub width: u32,
    pub access: Access,
    pub reset: u32,
    pub description: &'static str,
    pub values: Vec<EnumValue>,
}

impl Field {
    /// The field's mask within its register.
    pub fn mask(&self) -> u32 {
        (((1u64 << self.width) - 1) << self.lsb) as u32
    }
    /// Extracts the field from a register value.
    pub fn get(&self, reg: u32) -> u32 {
        (reg & self.mask()) >> self.lsb
    }
}

/// A register.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Register {
    pub name: &'static str,
    /// Word offset within its block (or within one element of an array).
    pub offset: u32,
    pub access: Access,
    pub reset: u32,
    pub description: &'static str,
    /// What reading or writing does besides storing or returning a value.
    pub side_effects: &'static str,
    pub fields: Vec<Field>,
}

impl Register {
    /// The field called `name`; panics if there is none (a map bug).
    pub fn field(&self, name: &str) -> &Field {
        self.find_field(name)
            .unwrap_or_else(|| panic!("register {} has no field {name}", self.name))
    }
    /// The field called `name`, if this build has it.
    pub fn find_field(&self, name: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.name == name)
    }
    /// Mask of every writable bit.
    pub fn writable_mask(&self) -> u32 {
        self.fields
            .iter()
            .filter(|f| f.access != Access::ReadOnly)
            .fold(0, |m, f| m | f.mask())
    }
}

/// Registers repeated once per channel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegisterArray {
    pub name: &'static str,
    pub count: u32,
    /// Word offset of element 0 within the block.
    pub offset: u32,
    /// Words between elements.
    pub stride: u32,
    pub registers: Vec<Register>,
}

impl RegisterArray {
    pub fn register(&self, name: &str) -> &Register {
        self.registers
            .iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("array {} has no register {name}", self.name))
    }
    /// Word offset within the block of `register` in element `index`.
    pub fn address(&self, index: u32, register: &str) -> u32 {
        assert!(
            index < self.count,
            "{}[{index}] out of range 0..{}",
            self.name,
            self.count
        );
        self.offset + index * self.stride + self.register(register).offset
    }
}

/// A block of registers at a base address.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    pub name: &'static str,
    pub description: &'static str,
    /// Word address of the block on its bus.
    pub base: u32,
    /// Address bits the block decodes.
    pub address_bits: u32,
    pub registers: Vec<Register>,
    pub arrays: Vec<RegisterArray>,
}

impl Block {
    pub fn register(&self, name: &str) -> &Register {
        self.registers
            .iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("block {} has no register {name}", self.name))
    }
    pub fn array(&self, name: &str) -> &RegisterArray {
        self.arrays
            .iter()
            .find(|a| a.name == name)
            .unwrap_or_else(|| panic!("block {} has no array {name}", self.name))
    }
    /// Every (word offset, register, array element) the block decodes.
    pub fn decoded(&self) -> Vec<(u32, &Register, Option<u32>)> {
        let mut out: Vec<(u32, &Register, Option<u32>)> =
            self.registers.iter().map(|r| (r.offset, r, None)).collect();
        for a in &self.arrays {
            for i in 0..a.count {
                for r in &a.registers {
                    out.push((a.offset + i * a.stride + r.offset, r, Some(i)));
                }
            }
        }
        out.sort_by_key(|x| x.0);
        out
    }
}

fn field(
    name: &'static str,
    lsb: u32,
    width: u32,
    access: Access,
    description: &'static str,
) -> Field {
    Field {
        name,
        lsb,
        width,
        access,
        reset: 0,
        description,
        values: Vec::new(),
    }
}

/// `f` with the reset value `reset`.
fn with_reset(mut f: Field, reset: u32) -> Field {
    f.reset = reset;
    f
}

fn reg(
    name: &'static str,
    offset: u32,
    access: Access,
    description: &'static str,
    side_effects: &'static str,
    fields: Vec<Field>,
) -> Register {
    Register {
        name,
        offset,
        access,
        reset: fields.iter().fold(0, |r, f| r | (f.reset << f.lsb)),
        description,
        side_effects,
        fields,
    }
}

/// A memory window on a bus: the shared RAM's MCU port.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Memory {
    pub name: &'static str,
    pub description: &'static str,
    /// Byte offset of word 0 from the start of the bus window.
    pub byte_offset: u32,
    /// Words in the window.
    pub words: u32,
    /// Bits per word; each word is one bus access.
    pub word_bits: u32,
}

/// What the MCU sees through `fsmc_bridge`: blocks of 32-bit registers and
/// memory windows at byte offsets from the FPGA's chip-select base.
///
/// The FSMC bus is 16 bits wide: pin `A[k]` is byte-address bit `k + 1`.
/// A 32-bit register is two halfwords, the low one at the lower address.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BusMap {
    pub name: &'static str,
    pub description: &'static str,
    /// Halfword address pins the bridge decodes (`A[ADDRESS_BITS-1:0]`).
    pub halfword_address_bits: u32,
    /// Register blocks; each block's `base` is its 32-bit word address.
    pub blocks: Vec<Block>,
    pub memories: Vec<Memory>,
}

impl BusMap {
    pub fn block(&self, name: &str) -> &Block {
        self.blocks
            .iter()
            .find(|b| b.name == name)
            .unwrap_or_else(|| panic!("map {} has no block {name}", self.name))
    }
    /// Byte offset of a block's first register.
    pub fn block_byte_offset(&self, name: &str) -> u32 {
        self.block(name).base * 4
    }
    /// Bytes the bus window spans.
    pub fn window_bytes(&self) -> u32 {
        2 << self.halfword_address_bits
    }
}

/// Halfword address pins of the MCU bus: an 8 KB window.
pub const MCU_HALFWORD_ADDRESS_BITS: u32 = 12;
/// Word address of the identity block on the MCU bus.
pub const MCU_ID_WORD_BASE: u32 = 0x000;
/// Word address of the counter bank on the MCU bus (byte 0x0400).
pub const MCU_COUNTER_WORD_BASE: u32 = 0x100;
/// Word address of the pulse generators on the MCU bus (byte 0x0800).
pub const MCU_PULSE_WORD_BASE: u32 = 0x200;
/// Word address of the safety block on the MCU bus (byte 0x0200).
pub const MCU_SAFETY_WORD_BASE: u32 = 0x080;
/// Word address of the servo DAC block on the MCU bus (byte 0x0040), in a
/// build with `servo_dac`.
pub const MCU_SERVO_WORD_BASE: u32 = 0x010;
/// Byte offset of the shared RAM's MCU port (halfword address 0x800: pin A11).
pub const MCU_RAM_BYTE_OFFSET: u32 = 0x1000;

/// The MCU's view of the gateware for `config`: ID, COUNTER, PULSE,
/// SAFETY, SERVO with `servo_dac` and, with the internal RAM, the shared
/// RAM window.
pub fn mcu_map(config: &crate::Config) -> BusMap {
    let build = |hash| {
        let mut counter = counter_bank_with(
            config.axes(),
            config.counter_width(),
            config.counter_features(),
        );
        counter.base = MCU_COUNTER_WORD_BASE;
        let mut pulse = pulse_bank(config.axes(), config.counter_width());
        pulse.base = MCU_PULSE_WORD_BASE;
        let mut safety = safety_io(config.axes());
        safety.base = MCU_SAFETY_WORD_BASE;
        let mut blocks = vec![id_block(config, hash), counter, pulse, safety];
        if config.servo_dac() {
            let mut servo = servo_dac(config.clock_hz());
            servo.base = MCU_SERVO_WORD_BASE;
            blocks.push(servo);
        }
        let mut memories = Vec::new();
        if config.isa_ram() == crate::IsaRam::Internal {
            memories.push(isa_bridge::shared_ram());
        }
        BusMap {
            name: "MOTIONHDL",
            description: "motionhdl motion-controller gateware, MCU bus (FSMC, 16-bit)",
            halfword_address_bits: MCU_HALFWORD_ADDRESS_BITS,
            blocks,
            memories,
        }
    };
    let hash = map_hash(&build(0));
    build(hash)
}

/// FNV-1a over a canonical text of the map, with ID.MAP_HASH's value zeroed
/// so that the hash does not depend on itself.
pub fn map_hash(map: &BusMap) -> u32 {
    let mut text = format!("{} {}\n", map.name, map.halfword_address_bits);
    for b in &map.blocks {
        text += &format!("block {} {} {}\n", b.name, b.base, b.address_bits);
        for (addr, r, index) in b.decoded() {
            let zero_hash = b.name == "ID" && r.name == "MAP_HASH";
            text += &format!(
                "reg {addr} {} {index:?} {:?} {}\n",
                r.name,
                r.access,
                if zero_hash { 0 } else { r.reset }
            );
            for f in &r.fields {
                let reset = if zero_hash { 0 } else { f.reset };
                text += &format!(
                    "field {} {} {} {:?} {reset}\n",
                    f.name, f.lsb, f.width, f.access
                );
                for v in &f.values {
                    text += &format!("value {} {}\n", v.name, v.value);
                }
            }
        }
    }
    for m in &map.memories {
        text += &format!(
            "memory {} {} {} {}\n",
            m.name, m.byte_offset, m.words, m.word_bits
        );
    }
    text.bytes().fold(0x811c_9dc5u32, |h, byte| {
        (h ^ u32::from(byte)).wrapping_mul(0x0100_0193)
    })
}
