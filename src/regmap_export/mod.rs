//! Firmware-side exports of the MCU register map
//! (`motionhdl_model::regmap::mcu_map`): a C header with its self-test, a
//! CMSIS-SVD file, JSON, Markdown and a `no_std` Rust module. Every number in
//! them is read from the one table; none is typed here.
//!
//! The MCU reaches the gateware over the STM32 FSMC, a 16-bit bus: every
//! 32-bit register is two halfword cycles, the low one first, and the
//! gateware relies on that order for tear-free reads, so firmware accesses
//! registers as 32-bit words. The shared RAM window holds 16-bit words.

pub mod c_header;
pub mod json;
pub mod markdown;
pub mod rust_module;
pub mod selftest;
pub mod svd;

use motionhdl_model::regmap::{Access, Block, BusMap, Memory, Register, RegisterArray};

/// Default base address of the window: STM32F4 FSMC bank 1, region 1
/// (chip select NE1), where the FPGA usually sits.
pub const FSMC_NE1_BASE: u32 = 0x6000_0000;

/// Bytes per register (every register is 32 bits wide).
pub const REGISTER_BYTES: u32 = 4;

/// What firmware must know about the bus, as one paragraph.
pub fn access_rule() -> &'static str {
    "The FSMC bus is 16 bits wide and every register is 32 bits: the FSMC \
     splits a 32-bit access into two halfword cycles, the low halfword (lower \
     address) first, and the gateware relies on that order to read a register \
     tear-free and to write it as a whole. Access registers only as 32-bit \
     words, never as halfwords or bytes. The shared RAM window holds 16-bit \
     words: access it as halfwords."
}

/// The access type as the documentation spells it.
pub fn access_text(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "read-only",
        Access::WriteOnly => "write-only",
        Access::ReadWrite => "read-write",
        Access::WriteOneToClear => "read, write 1 to clear",
    }
}

/// A short access tag: RO, WO, RW, W1C.
pub fn access_tag(a: Access) -> &'static str {
    match a {
        Access::ReadOnly => "RO",
        Access::WriteOnly => "WO",
        Access::ReadWrite => "RW",
        Access::WriteOneToClear => "W1C",
    }
}

/// Byte offset of a block from the window base.
pub fn block_byte_offset(b: &Block) -> u32 {
    b.base * REGISTER_BYTES
}

/// Bytes the block decodes.
pub fn block_span_bytes(b: &Block) -> u32 {
    (1u32 << b.address_bits) * REGISTER_BYTES
}

/// Bytes of a memory window.
pub fn memory_bytes(m: &Memory) -> u32 {
    m.words * m.word_bits / 8
}

/// Bytes of one array element (its stride).
pub fn stride_bytes(a: &RegisterArray) -> u32 {
    a.stride * REGISTER_BYTES
}

/// One member of a register struct, in address order.
pub enum Member<'a> {
    Register(&'a Register),
    Array(&'a RegisterArray),
    /// `words` unused 32-bit words.
    Reserved {
        words: u32,
    },
}

/// The members of a struct holding `registers` and `arrays`, with reserved
/// words filling every gap, and the struct's size in words. With
/// `size = Some(words)` the struct is padded to that size.
pub fn layout<'a>(
    registers: &'a [Register],
    arrays: &'a [RegisterArray],
    size: Option<u32>,
) -> (Vec<(u32, Member<'a>)>, u32) {
    let mut items: Vec<(u32, u32, Member<'a>)> = registers
        .iter()
        .map(|r| (r.offset, 1, Member::Register(r)))
        .chain(
            arrays
                .iter()
                .map(|a| (a.offset, a.count * a.stride, Member::Array(a))),
        )
        .collect();
    items.sort_by_key(|i| i.0);
    let mut out = Vec::new();
    let mut at = 0;
    for (offset, words, m) in items {
        assert!(offset >= at, "overlapping registers at word {offset}");
        if offset > at {
            out.push((at, Member::Reserved { words: offset - at }));
        }
        out.push((offset, m));
        at = offset + words;
    }
    if let Some(size) = size {
        assert!(size >= at, "registers past the struct size {size}");
        if size > at {
            out.push((at, Member::Reserved { words: size - at }));
        }
        at = size;
    }
    (out, at)
}

/// Size in bytes of the C struct of one array element: its stride.
pub fn element_struct_bytes(a: &RegisterArray) -> u32 {
    layout(&a.registers, &[], Some(a.stride)).1 * REGISTER_BYTES
}

/// Size in bytes of the C struct of a block: up to its last register.
pub fn block_struct_bytes(b: &Block) -> u32 {
    layout(&b.registers, &b.arrays, None).1 * REGISTER_BYTES
}

/// One member of the whole-window struct.
pub enum WindowMember<'a> {
    Block(&'a Block),
    Memory(&'a Memory),
    /// `bytes` unused bytes.
    Reserved {
        bytes: u32,
    },
    /// `bytes` of A11 = 1 addresses past the memory: the RAM port decodes
    /// A[9:0] only, so they are the memory again.
    Mirror {
        of: &'a Memory,
        bytes: u32,
    },
    /// `bytes` of A11 = 1 addresses in a build without a RAM window: the
    /// top's window port (`window_addr`, `window_rdata`...), the board's.
    WindowPort {
        bytes: u32,
    },
}

/// The window struct's members with their byte offsets, and its size.
pub fn window_layout(map: &BusMap) -> (Vec<(u32, WindowMember<'_>)>, u32) {
    let mut items: Vec<(u32, u32, WindowMember)> = map
        .blocks
        .iter()
        .map(|b| {
            (
                block_byte_offset(b),
                block_struct_bytes(b),
                WindowMember::Block(b),
            )
        })
        .chain(
            map.memories
                .iter()
                .map(|m| (m.byte_offset, memory_bytes(m), WindowMember::Memory(m))),
        )
        .collect();
    items.sort_by_key(|i| i.0);
    let mut out = Vec::new();
    let mut at = 0;
    for (offset, bytes, m) in items {
        assert!(offset >= at, "overlapping blocks at byte {offset:#x}");
        if offset > at {
            out.push((at, WindowMember::Reserved { bytes: offset - at }));
        }
        out.push((offset, m));
        at = offset + bytes;
    }
    // The rest of the window: every byte of it is described.
    let window = map.window_bytes();
    // A11 = 1 (a halfword address bit): bytes from 2^12 on.
    let port_start = 2 << motionhdl_model::fsmc_bridge::RAM_WINDOW_BIT;
    if at < port_start {
        out.push((
            at,
            WindowMember::Reserved {
                bytes: port_start - at,
            },
        ));
        at = port_start;
    }
    if at < window {
        let bytes = window - at;
        out.push(match map.memories.first() {
            Some(of) => {
                let halfword = (at / 2) as u16;
                assert_eq!(
                    motionhdl_model::fsmc_bridge::ram_word(halfword),
                    0,
                    "the RAM port decodes byte {at:#x} as its word 0"
                );
                (at, WindowMember::Mirror { of, bytes })
            }
            None => (at, WindowMember::WindowPort { bytes }),
        });
        at = window;
    }
    (out, at)
}

/// One register as the MCU sees it: array registers once per element.
pub struct Instance<'a> {
    pub block: &'a Block,
    /// The array and the element index, for array registers.
    pub array: Option<(&'a RegisterArray, u32)>,
    pub register: &'a Register,
    /// Byte offset from the window base.
    pub byte_offset: u32,
}

impl Instance<'_> {
    /// `BLOCK.REG` or `BLOCK.ARRAY[n].REG`.
    pub fn path(&self) -> String {
        match self.array {
            None => format!("{}.{}", self.block.name, self.register.name),
            Some((a, i)) => format!("{}.{}[{i}].{}", self.block.name, a.name, self.register.name),
        }
    }
}

/// Every register of the map, in address order.
pub fn instances(map: &BusMap) -> Vec<Instance<'_>> {
    let mut out = Vec::new();
    for b in &map.blocks {
        for r in &b.registers {
            out.push(Instance {
                block: b,
                array: None,
                register: r,
                byte_offset: block_byte_offset(b) + r.offset * REGISTER_BYTES,
            });
        }
        for a in &b.arrays {
            for i in 0..a.count {
                for r in &a.registers {
                    out.push(Instance {
                        block: b,
                        array: Some((a, i)),
                        register: r,
                        byte_offset: block_byte_offset(b) + a.address(i, r.name) * REGISTER_BYTES,
                    });
                }
            }
        }
    }
    out.sort_by_key(|i| i.byte_offset);
    out
}

/// The value of ID.MAP_HASH (panics if the map has none).
pub fn map_hash(map: &BusMap) -> u32 {
    map.block("ID").register("MAP_HASH").reset
}

/// The value of ID.MAGIC (panics if the map has none).
pub fn id_magic(map: &BusMap) -> u32 {
    map.block("ID").register("MAGIC").reset
}

pub use crate::text::wrap;

/// A register's description, its side effects, and notes on write-only and
/// write-one-to-clear access, as one text.
pub fn register_doc(r: &Register) -> String {
    let mut text = r.description.to_string();
    if !r.side_effects.is_empty() {
        text.push(' ');
        text.push_str(r.side_effects);
    }
    if r.access == Access::WriteOnly {
        text.push_str(" Write-only: reads return 0.");
    }
    if r.fields.iter().any(|f| f.access == Access::WriteOneToClear) {
        text.push_str(" Write 1 to a write-1-to-clear bit to clear it; 0 leaves it.");
    }
    text
}

/// Bits of a field as `bit n` or `bits m:n`.
pub fn bits_text(lsb: u32, width: u32) -> String {
    if width == 1 {
        format!("bit {lsb}")
    } else {
        format!("bits {}:{lsb}", lsb + width - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use motionhdl_model::regmap::{mcu_map, RegisterArray};
    use motionhdl_model::{Config, IsaRam};

    #[test]
    fn layout_fills_gaps_and_pads_to_the_stride() {
        let map = mcu_map(&Config::default());
        let ch = map.block("COUNTER").array("CH");
        let (members, words) = layout(&ch.registers, &[], Some(ch.stride));
        assert_eq!(words, ch.stride);
        let reserved: Vec<(u32, u32)> = members
            .iter()
            .filter_map(|(at, m)| match m {
                Member::Reserved { words } => Some((*at, *words)),
                _ => None,
            })
            .collect();
        assert_eq!(reserved, vec![(6, 2)]);
        assert_eq!(element_struct_bytes(ch), 32);
        // COUNTER: INFO, SNAPSHOT, PRESET, 5 reserved words, CH[4].
        let counter = map.block("COUNTER");
        assert_eq!(block_struct_bytes(counter), (8 + 4 * 8) * 4);
    }

    #[test]
    #[should_panic(expected = "registers past the struct size")]
    fn layout_refuses_a_stride_smaller_than_the_element() {
        let map = mcu_map(&Config::default());
        let mut ch: RegisterArray = map.block("COUNTER").array("CH").clone();
        ch.stride = 4;
        element_struct_bytes(&ch);
    }

    #[test]
    fn window_layout_and_instances_follow_the_table() {
        for ram in [IsaRam::Internal, IsaRam::External] {
            let map = mcu_map(&Config::default().with_isa_ram(ram));
            let (members, size) = window_layout(&map);
            let offsets: Vec<u32> = members.iter().map(|m| m.0).collect();
            // ID (10 words) and padding, SAFETY at 0x200 (37 words, to
            // 0x294) and padding, COUNTER at 0x400 (to 0x4a0) and padding,
            // PULSE at 0x800 (16 + 4 x 16 words, to 0x940), then padding
            // and the RAM at 0x1000.
            if ram == IsaRam::Internal {
                // The RAM again from 0x1800 (A10 is not decoded).
                assert_eq!(
                    offsets,
                    vec![0, 0x28, 0x200, 0x294, 0x400, 0x4a0, 0x800, 0x940, 0x1000, 0x1800]
                );
                assert!(matches!(
                    members[9].1,
                    WindowMember::Mirror { bytes: 0x800, .. }
                ));
            } else {
                // Reads 0 to 0x1000, then the board's window port.
                assert_eq!(
                    offsets,
                    vec![0, 0x28, 0x200, 0x294, 0x400, 0x4a0, 0x800, 0x940, 0x1000]
                );
                assert!(matches!(
                    members[8].1,
                    WindowMember::WindowPort { bytes: 0x1000 }
                ));
            }
            assert_eq!(size, 0x2000, "every byte of the window");
            let inst = instances(&map);
            assert_eq!(inst.len(), 10 + 3 + 4 * 6 + 2 + 4 * 16 + 37);
            assert!(inst.windows(2).all(|w| w[0].byte_offset < w[1].byte_offset));
            let status = inst
                .iter()
                .find(|i| i.path() == "COUNTER.CH[3].STATUS")
                .unwrap();
            assert_eq!(status.byte_offset, 0x400 + 0x20 + 3 * 0x20 + 0x10);
        }
        // The servo card's map: SERVO at 0x40 (6 registers, 2 reserved
        // words, CH[4] of CODE and OUTPUT: 16 words, to 0x80) after ID.
        let map = mcu_map(&Config::default().with_servo_dac(true));
        let (members, size) = window_layout(&map);
        let offsets: Vec<u32> = members.iter().map(|m| m.0).collect();
        assert_eq!(
            offsets,
            vec![0, 0x28, 0x40, 0x80, 0x200, 0x294, 0x400, 0x4a0, 0x800, 0x940, 0x1000, 0x1800]
        );
        assert_eq!(size, 0x2000);
        let code = instances(&map)
            .into_iter()
            .find(|i| i.path() == "SERVO.CH[3].CODE")
            .unwrap();
        assert_eq!(code.byte_offset, 0x40 + (8 + 3 * 2) * 4);
    }

    #[test]
    fn wrap_keeps_words_and_paragraphs() {
        assert_eq!(wrap("aa bb cc", 5), vec!["aa bb", "cc"]);
        assert_eq!(wrap("a\n\nb", 80), vec!["a", "", "b"]);
        assert_eq!(bits_text(3, 1), "bit 3");
        assert_eq!(bits_text(8, 8), "bits 15:8");
    }

    #[test]
    fn literal_and_name_helpers() {
        assert_eq!(rust_module::hex(0x4d48_444c, 8), "0x4d48_444c");
        assert_eq!(rust_module::hex(0x20, 4), "0x0020");
        assert_eq!(rust_module::hex(0x1c, 1), "0x1c");
        assert_eq!(rust_module::module_name("CH"), "ch");
        assert_eq!(rust_module::module_name("TYPE"), "r#type");
        assert_eq!(c_header::hex(0x20), "0x0020u");
        assert_eq!(c_header::hex(0x6000_0000), "0x60000000u");
    }
}
