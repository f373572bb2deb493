//! The register map: the one source of truth for every address, field
//! position, access type and reset value. The HDL address decoders, the
//! model and every export (C headers, SVD, documentation) read it from here.
//!
//! Addresses are word addresses on the internal 32-bit register bus.

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
        self.fields
            .iter()
            .find(|f| f.name == name)
            .unwrap_or_else(|| panic!("register {} has no field {name}", self.name))
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

/// Counting modes of CTRL.MODE.
pub mod mode {
    pub const X4: u32 = 0;
    pub const X2: u32 = 1;
    pub const X1: u32 = 2;
    pub const PULSE_DIR: u32 = 3;
    pub const CW_CCW: u32 = 4;
}

/// Width of the per-channel error counter in the gateware.
pub const ERR_COUNT_BITS: u32 = 8;

/// The counter bank's registers for `axes` channels of `width`-bit counters
/// (see docs/counter_bank.md).
pub fn counter_bank(axes: u32, width: u32) -> Block {
    use Access::*;
    assert!(
        (1..=16).contains(&axes),
        "axes = {axes} out of range 1..=16"
    );
    assert!(
        (2..=32).contains(&width),
        "width = {width} out of range 2..=32"
    );
    let mut info_axes = field("AXES", 0, 5, ReadOnly, "Number of channels.");
    info_axes.reset = axes;
    let mut info_width = field("WIDTH", 8, 6, ReadOnly, "Counter width in bits.");
    info_width.reset = width;
    let mut info_err = field(
        "ERR_BITS",
        16,
        4,
        ReadOnly,
        "Width of each channel's error counter.",
    );
    info_err.reset = ERR_COUNT_BITS;
    let mut mode = field("MODE", 0, 3, ReadWrite, "Counting mode.");
    mode.values = vec![
        EnumValue {
            name: "X4",
            value: mode::X4,
            description: "Quadrature, every edge of A and B.",
        },
        EnumValue {
            name: "X2",
            value: mode::X2,
            description: "Quadrature, every edge of A.",
        },
        EnumValue {
            name: "X1",
            value: mode::X1,
            description: "Quadrature, one count per A cycle.",
        },
        EnumValue {
            name: "PULSE_DIR",
            value: mode::PULSE_DIR,
            description: "A = pulse (rising edge), B = direction (1 = down).",
        },
        EnumValue {
            name: "CW_CCW",
            value: mode::CW_CCW,
            description: "A pulses count up, B pulses count down.",
        },
    ];
    Block {
        name: "COUNTER",
        description: "Quadrature/pulse counter bank",
        base: 0,
        address_bits: 8,
        registers: vec![
            reg(
                "INFO",
                0,
                ReadOnly,
                "Build parameters of the bank.",
                "",
                vec![info_axes, info_width, info_err],
            ),
            reg(
                "SNAPSHOT",
                1,
                WriteOnly,
                "Capture every channel's COUNT, INDEX and STATUS in the same clock.",
                "Any write captures; the data is ignored.",
                vec![],
            ),
            reg(
                "PRESET",
                2,
                ReadWrite,
                "Value a channel's CMD.LOAD copies into its counter. Reads sign-extended.",
                "",
                vec![field(
                    "VALUE",
                    0,
                    32,
                    ReadWrite,
                    "Preset value, taken modulo 2^WIDTH.",
                )],
            ),
        ],
        arrays: vec![RegisterArray {
            name: "CH",
            count: axes,
            offset: 8,
            stride: 8,
            registers: vec![
                reg(
                    "CTRL",
                    0,
                    ReadWrite,
                    "Channel configuration.",
                    "",
                    vec![
                        mode,
                        field("REVERSE", 3, 1, ReadWrite, "Swap up and down."),
                        field(
                            "ERR_EN",
                            4,
                            1,
                            ReadWrite,
                            "Latch illegal quadrature transitions into STATUS.ERR and ERR_COUNT.",
                        ),
                        field("IDX_INVERT", 5, 1, ReadWrite, "Index is active low."),
                        field(
                            "IDX_LATCH",
                            6,
                            1,
                            ReadWrite,
                            "Latch the count into INDEX on an index event.",
                        ),
                        field(
                            "IDX_CLEAR",
                            7,
                            1,
                            ReadWrite,
                            "Clear the count on an index event.",
                        ),
                        field(
                            "IDX_GATE",
                            8,
                            1,
                            ReadWrite,
                            "Accept the index only while A and B are both high.",
                        ),
                        field(
                            "IDX_ONESHOT",
                            9,
                            1,
                            ReadWrite,
                            "Index actions only while STATUS.ARMED; the first event disarms.",
                        ),
                        field(
                            "FILTER_AB",
                            16,
                            4,
                            ReadWrite,
                            "A/B filter: a level is accepted after FILTER_AB+1 equal samples.",
                        ),
                        field("FILTER_Z", 20, 4, ReadWrite, "Index filter, as FILTER_AB."),
                    ],
                ),
                reg(
                    "CMD",
                    1,
                    WriteOnly,
                    "Channel commands; write 1 to a bit to act.",
                    "CLEAR wins over LOAD, both over an index clear and counting in that clock.",
                    vec![
                        field("CLEAR", 0, 1, WriteOnly, "Set the count to 0."),
                        field("LOAD", 1, 1, WriteOnly, "Set the count to PRESET."),
                        field("ARM", 2, 1, WriteOnly, "Arm the one-shot index."),
                        field(
                            "CLEAR_STATUS",
                            3,
                            1,
                            WriteOnly,
                            "Clear STATUS.ERR, ERR_COUNT and SEEN.",
                        ),
                    ],
                ),
                reg(
                    "COUNT",
                    2,
                    ReadOnly,
                    "Count at the last SNAPSHOT, sign-extended from WIDTH bits.",
                    "",
                    vec![field(
                        "VALUE",
                        0,
                        32,
                        ReadOnly,
                        "Two's complement count; wraps modulo 2^WIDTH.",
                    )],
                ),
                reg(
                    "INDEX",
                    3,
                    ReadOnly,
                    "Index latch at the last SNAPSHOT, sign-extended from WIDTH bits.",
                    "",
                    vec![field(
                        "VALUE",
                        0,
                        32,
                        ReadOnly,
                        "Count captured at the last latching index event.",
                    )],
                ),
                reg(
                    "STATUS",
                    4,
                    ReadOnly,
                    "Status at the last SNAPSHOT.",
                    "",
                    vec![
                        field(
                            "ERR",
                            0,
                            1,
                            ReadOnly,
                            "Sticky: an illegal quadrature transition was seen.",
                        ),
                        field("ARMED", 1, 1, ReadOnly, "One-shot index armed."),
                        field("SEEN", 2, 1, ReadOnly, "Sticky: an index event was seen."),
                        field("A", 4, 1, ReadOnly, "Accepted level of A."),
                        field("B", 5, 1, ReadOnly, "Accepted level of B."),
                        field(
                            "Z",
                            6,
                            1,
                            ReadOnly,
                            "Accepted level of Z (before IDX_INVERT).",
                        ),
                        field(
                            "ERR_COUNT",
                            8,
                            ERR_COUNT_BITS,
                            ReadOnly,
                            "Illegal transitions seen, saturating.",
                        ),
                    ],
                ),
            ],
        }],
    }
}

/// Words in the shared dual-port RAM behind the ISA bridge (2 KB).
pub const ISA_RAM_WORDS: u32 = 1024;
/// Bits of the ISA bridge's address counter.
pub const ISA_ADDR_BITS: u32 = 10;

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
                "A write loads ADDR and AUTO_INC and clears the sticky bits written as 1.",
                status_fields(),
            ),
        ],
        arrays: vec![],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counter_bank_addresses_are_distinct_and_fit() {
        for axes in 1..=16 {
            let b = counter_bank(axes, 28);
            let d = b.decoded();
            let mut addrs: Vec<u32> = d.iter().map(|x| x.0).collect();
            addrs.dedup();
            assert_eq!(addrs.len(), d.len(), "overlapping addresses at {axes} axes");
            assert!(addrs.iter().all(|a| *a < (1 << b.address_bits)));
        }
    }

    #[test]
    fn fields_do_not_overlap_and_fit_32_bits() {
        let b = counter_bank(4, 28);
        let regs = b
            .registers
            .iter()
            .chain(b.arrays.iter().flat_map(|a| a.registers.iter()));
        for r in regs {
            let mut used = 0u64;
            for f in &r.fields {
                assert!(f.lsb + f.width <= 32, "{}.{}", r.name, f.name);
                let m = u64::from(f.mask());
                assert_eq!(used & m, 0, "{}.{} overlaps", r.name, f.name);
                used |= m;
            }
        }
    }

    #[test]
    fn info_reset_value_encodes_the_build() {
        let b = counter_bank(4, 28);
        assert_eq!(
            b.register("INFO").reset,
            4 | (28 << 8) | (ERR_COUNT_BITS << 16)
        );
        assert_eq!(b.array("CH").address(1, "COUNT"), 8 + 8 + 2);
        assert_eq!(b.array("CH").register("CTRL").writable_mask(), 0x00ff_03ff);
    }
}
