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

/// The pulse generators: per axis an NCO rate, step timing, output mode
/// and the position of emitted steps; RUN starts and stops axes together.
pub fn pulse_bank(axes: u32, width: u32) -> Block {
    use Access::*;
    assert!(
        (1..=16).contains(&axes),
        "axes = {axes} out of range 1..=16"
    );
    assert!(
        (2..=32).contains(&width),
        "width = {width} out of range 2..=32"
    );
    let mut info_axes = field("AXES", 0, 5, ReadOnly, "Number of pulse generators.");
    info_axes.reset = axes;
    let mut info_width = field("WIDTH", 8, 6, ReadOnly, "POSITION width in bits.");
    info_width.reset = width;
    let mut mode = field(
        "MODE",
        0,
        1,
        ReadWrite,
        "Output mode: the pulse-mode selector's K input.",
    );
    mode.values = vec![
        EnumValue {
            name: "PULSE_DIR",
            value: 0,
            description: "F1 = step (S1), F2 = direction (S2, 1 = negative).",
        },
        EnumValue {
            name: "CW_CCW",
            value: 1,
            description:
                "F1 = steps in the positive direction, F2 = steps in the negative direction.",
        },
    ];
    let timing = |lo: &'static str, hi: &'static str, lo_doc, hi_doc| {
        vec![
            field(lo, 0, 16, ReadWrite, lo_doc),
            field(hi, 16, 16, ReadWrite, hi_doc),
        ]
    };
    Block {
        name: "PULSE",
        description: "Step/pulse generators (docs/pulse_generator.md)",
        base: 0,
        address_bits: 9,
        registers: vec![
            reg("INFO", 0, ReadOnly, "Build parameters of the pulse generators.", "", vec![info_axes, info_width]),
            reg(
                "RUN",
                1,
                ReadWrite,
                "Bit n runs axis n's NCO. One write starts (or stops) every axis it names in the same clock.",
                "Stopping an axis stops new steps; steps already commanded still go out.",
                vec![field("AXES", 0, axes, ReadWrite, "One bit per axis.")],
            ),
        ],
        arrays: vec![RegisterArray {
            name: "AX",
            count: axes,
            offset: 16,
            stride: 16,
            registers: vec![
                reg(
                    "CTRL",
                    0,
                    ReadWrite,
                    "Output mode.",
                    "",
                    vec![
                        mode,
                        field(
                            "QUADRATURE",
                            1,
                            1,
                            ReadWrite,
                            "F1/F2 = quadrature A/B instead of the selector: one A or B edge per step (count it x4).",
                        ),
                        field(
                            "MOVES",
                            2,
                            1,
                            ReadWrite,
                            "The NCO runs the segment FIFO's moves instead of RATE.",
                        ),
                    ],
                ),
                reg(
                    "RATE",
                    1,
                    ReadWrite,
                    "Signed NCO rate: steps per clock = RATE / 2^32, up to half the clock.",
                    "",
                    vec![field("VALUE", 0, 32, ReadWrite, "Two's complement; the sign is the direction.")],
                ),
                reg(
                    "STEP_TIMING",
                    2,
                    ReadWrite,
                    "Minimum step pulse length and space, in clocks (0 counts as 1).",
                    "",
                    timing("STEP_LEN", "STEP_SPACE", "S1 high at least this long.", "S1 low at least this long between steps."),
                ),
                reg(
                    "DIR_TIMING",
                    3,
                    ReadWrite,
                    "Minimum direction set-up and hold, in clocks (0 counts as 1).",
                    "",
                    timing("DIR_SETUP", "DIR_HOLD", "S2 stable at least this long before S1 rises.", "S1 low at least this long before S2 changes."),
                ),
                reg(
                    "POSITION",
                    4,
                    ReadOnly,
                    "Steps emitted at the counter bank's last SNAPSHOT, sign-extended from WIDTH bits.",
                    "",
                    vec![field("VALUE", 0, 32, ReadOnly, "Two's complement; wraps modulo 2^WIDTH.")],
                ),
                reg(
                    "STATUS",
                    5,
                    ReadOnly,
                    "Live state of the axis.",
                    "",
                    vec![
                        field("PENDING", 0, 16, ReadOnly, "Steps commanded but not yet emitted, signed."),
                        field("BUSY", 16, 1, ReadOnly, "Steps pending or S1 high."),
                        field("MOVING", 17, 1, ReadOnly, "A segment is running."),
                        field(
                            "DONE",
                            18,
                            1,
                            ReadOnly,
                            "Sticky: every pushed segment has commanded all its steps (cleared by SEG_PUSH). DONE and not BUSY: the move is out.",
                        ),
                        field(
                            "OVERFLOW",
                            19,
                            1,
                            ReadOnly,
                            "Sticky: a SEG_PUSH found the FIFO full and was dropped (cleared by writing CTRL).",
                        ),
                        field("FIFO_LEVEL", 20, 3, ReadOnly, "Segments waiting in the FIFO (0..=2)."),
                    ],
                ),
                reg(
                    "SEG_STEPS",
                    6,
                    WriteOnly,
                    "Next segment: steps to command (unsigned).",
                    "Written straight into the FIFO's free tail slot; dropped while the FIFO is full (write a segment while FIFO_LEVEL < 2). Write all three SEG_* before each SEG_PUSH: a field not written keeps the slot's old contents.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Steps.")],
                ),
                reg(
                    "SEG_RATE",
                    7,
                    WriteOnly,
                    "Next segment: starting NCO rate (signed, as RATE).",
                    "Written straight into the FIFO's free tail slot; dropped while the FIFO is full (write a segment while FIFO_LEVEL < 2). Write all three SEG_* before each SEG_PUSH: a field not written keeps the slot's old contents.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Two's complement; the sign is the direction.")],
                ),
                reg(
                    "SEG_ACCEL",
                    8,
                    WriteOnly,
                    "Next segment: added to the rate on every clock the NCO advances (signed).",
                    "Written straight into the FIFO's free tail slot; dropped while the FIFO is full (write a segment while FIFO_LEVEL < 2). Write all three SEG_* before each SEG_PUSH: a field not written keeps the slot's old contents.",
                    vec![field("VALUE", 0, 32, WriteOnly, "Two's complement.")],
                ),
                reg(
                    "SEG_PUSH",
                    9,
                    WriteOnly,
                    "Push {SEG_STEPS, SEG_RATE, SEG_ACCEL} into the axis's segment FIFO (2 deep, besides the segment running).",
                    "Any write pushes; the data is ignored. A push into a full FIFO is dropped and sets STATUS.OVERFLOW.",
                    vec![],
                ),
            ],
        }],
    }
}

// The SEG_PUSH and FIFO_LEVEL descriptions above say how deep the FIFO is.
const _: () = assert!(crate::pulse::SEGMENT_FIFO_DEPTH == 2);

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
/// Byte offset of the shared RAM's MCU port (halfword address 0x800: pin A11).
pub const MCU_RAM_BYTE_OFFSET: u32 = 0x1000;
/// ID.MAGIC: "MHDL" in ASCII, most significant byte first.
pub const ID_MAGIC: u32 = 0x4D48_444C;

/// `VERSION` of this crate (the workspace version) as MAJOR, MINOR, PATCH.
pub fn gateware_version() -> (u32, u32, u32) {
    let mut parts = env!("CARGO_PKG_VERSION")
        .split(['.', '-', '+'])
        .map(|p| p.parse::<u32>().unwrap_or(0));
    let mut next = || parts.next().unwrap_or(0);
    (next(), next(), next())
}

fn ro_value(
    name: &'static str,
    lsb: u32,
    width: u32,
    reset: u32,
    description: &'static str,
) -> Field {
    let mut f = field(name, lsb, width, Access::ReadOnly, description);
    f.reset = reset;
    f
}

/// The identity block, in the spirit of hostmot2's IDROM: firmware reads it
/// first to check that it talks to the gateware it was built for. Every
/// register is read-only and holds its reset value for ever.
pub fn id_block(config: &crate::Config, map_hash: u32) -> Block {
    use Access::*;
    let (major, minor, patch) = gateware_version();
    let ram_internal = config.isa_ram() == crate::IsaRam::Internal;
    let one =
        |name, offset, description, f: Field| reg(name, offset, ReadOnly, description, "", vec![f]);
    let mut isa_ram = ro_value(
        "ISA_RAM",
        16,
        1,
        u32::from(!ram_internal),
        "Where the ISA bridge's shared RAM is.",
    );
    isa_ram.values = vec![
        EnumValue {
            name: "INTERNAL",
            value: 0,
            description: "Block RAM; its MCU port is the RAM window of this bus.",
        },
        EnumValue {
            name: "EXTERNAL",
            value: 1,
            description:
                "External dual-port SRAM; the MCU reaches it directly, not through this bus.",
        },
    ];
    Block {
        name: "ID",
        description: "Identity: what gateware this is and where its blocks are",
        base: MCU_ID_WORD_BASE,
        address_bits: 4,
        registers: vec![
            one("MAGIC", 0, "Constant cookie \"MHDL\": the FPGA is configured and the bus works.",
                ro_value("VALUE", 0, 32, ID_MAGIC, "0x4D48444C.")),
            reg("VERSION", 1, ReadOnly, "motionhdl version the gateware was generated by.", "", vec![
                ro_value("PATCH", 0, 8, patch, "Patch version."),
                ro_value("MINOR", 8, 8, minor, "Minor version."),
                ro_value("MAJOR", 16, 8, major, "Major version."),
            ]),
            one("CLOCK_HZ", 2, "FPGA clock frequency the gateware was built for, in Hz.",
                ro_value("VALUE", 0, 32, config.clock_hz() as u32, "Hz.")),
            reg("CONFIG", 3, ReadOnly, "Build configuration.", "", vec![
                ro_value("AXES", 0, 5, config.axes(), "Counter channels (and pulse generators)."),
                ro_value("COUNTER_WIDTH", 8, 6, config.counter_width(), "Counter width in bits."),
                isa_ram,
            ]),
            one("COUNTER_BASE", 4, "Byte offset of the COUNTER block from the bus window's base.",
                ro_value("VALUE", 0, 32, MCU_COUNTER_WORD_BASE * 4, "Bytes.")),
            one("PULSE_BASE", 8, "Byte offset of the PULSE block (pulse generators) from the bus window's base.",
                ro_value("VALUE", 0, 32, MCU_PULSE_WORD_BASE * 4, "Bytes.")),
            one("RAM_BASE", 5, "Byte offset of the shared RAM window; 0 when the RAM is external.",
                ro_value("VALUE", 0, 32, if ram_internal { MCU_RAM_BYTE_OFFSET } else { 0 }, "Bytes.")),
            one("RAM_WORDS", 6, "16-bit words in the shared RAM window; 0 when the RAM is external.",
                ro_value("VALUE", 0, 32, if ram_internal { ISA_RAM_WORDS } else { 0 }, "Words.")),
            one("MAP_HASH", 7, "FNV-1a hash of the register map (every block, register and field, without this value).",
                ro_value("VALUE", 0, 32, map_hash, "Compare with MOTIONHDL_MAP_HASH from the generated header.")),
        ],
        arrays: vec![],
    }
}

/// The MCU's view of the gateware for `config`: ID, COUNTER, PULSE and,
/// with the internal RAM, the shared RAM window.
pub fn mcu_map(config: &crate::Config) -> BusMap {
    let build = |hash| {
        let mut counter = counter_bank(config.axes(), config.counter_width());
        counter.base = MCU_COUNTER_WORD_BASE;
        let mut pulse = pulse_bank(config.axes(), config.counter_width());
        pulse.base = MCU_PULSE_WORD_BASE;
        let mut memories = Vec::new();
        if config.isa_ram() == crate::IsaRam::Internal {
            memories.push(Memory {
                name: "SHARED_RAM",
                description: "The MCU/DSP port of the 1 K x 16 RAM shared with the PC (ISA bridge). One word per 16-bit access.",
                byte_offset: MCU_RAM_BYTE_OFFSET,
                words: ISA_RAM_WORDS,
                word_bits: 16,
            });
        }
        BusMap {
            name: "MOTIONHDL",
            description: "motionhdl motion-controller gateware, MCU bus (FSMC, 16-bit)",
            halfword_address_bits: MCU_HALFWORD_ADDRESS_BITS,
            blocks: vec![id_block(config, hash), counter, pulse],
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

    #[test]
    fn mcu_map_blocks_do_not_overlap_and_fit_the_window() {
        use crate::{Config, IsaRam};
        for ram in [IsaRam::Internal, IsaRam::External] {
            for axes in [1, 4, 16] {
                let map = mcu_map(&Config::new(axes, 32, 50_000_000).unwrap().with_isa_ram(ram));
                let mut spans: Vec<(u32, u32, &str)> = map
                    .blocks
                    .iter()
                    .map(|b| (b.base * 4, (b.base + (1 << b.address_bits)) * 4, b.name))
                    .chain(map.memories.iter().map(|m| {
                        (
                            m.byte_offset,
                            m.byte_offset + m.words * m.word_bits / 8,
                            m.name,
                        )
                    }))
                    .collect();
                spans.sort();
                for w in spans.windows(2) {
                    assert!(w[0].1 <= w[1].0, "{} overlaps {}", w[0].2, w[1].2);
                }
                assert!(spans.last().unwrap().1 <= map.window_bytes());
                for b in &map.blocks {
                    assert_eq!(b.base % (1 << b.address_bits), 0, "{} not aligned", b.name);
                }
            }
        }
    }

    #[test]
    fn id_block_describes_the_map() {
        let config = crate::Config::default();
        let map = mcu_map(&config);
        let id = map.block("ID");
        assert_eq!(id.register("MAGIC").reset, 0x4D48_444C);
        assert_eq!(&ID_MAGIC.to_be_bytes(), b"MHDL");
        assert_eq!(
            id.register("COUNTER_BASE").reset,
            map.block_byte_offset("COUNTER")
        );
        assert_eq!(id.register("CLOCK_HZ").reset, 50_000_000);
        assert_eq!(id.register("CONFIG").reset, 4 | (28 << 8));
        assert_eq!(id.register("MAP_HASH").reset, map_hash(&map));
        // The hash sees the rest of the map.
        let other = mcu_map(&crate::Config::new(5, 28, 50_000_000).unwrap());
        assert_ne!(other.block("ID").register("MAP_HASH").reset, map_hash(&map));
    }
}
