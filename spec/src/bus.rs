//! The register bus every block's registers sit on (docs/counter_bank.md,
//! "Register bus"), and the arithmetic of its words: one cycle, the
//! instance parameters of a counter, wrap and sign extension.

use crate::regmap;
pub use crate::CounterFeatures;

/// Parameters of a channel/bank instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CounterParams {
    /// Counter width W in bits (2..=32).
    pub width: u32,
    /// Error counter width E in bits (1..=[`regmap::ERR_COUNT_BITS`]).
    pub err_bits: u32,
    /// The channel's optional features ([`CounterFeatures`]).
    pub features: CounterFeatures,
}

impl CounterParams {
    /// Panics when a parameter is outside the range the HDL accepts: a model
    /// of an instance that cannot be built would compare against nothing.
    pub fn new(width: u32, err_bits: u32) -> Self {
        assert!(
            (2..=32).contains(&width),
            "counter width = {width} out of range 2..=32"
        );
        assert!(
            (1..=regmap::ERR_COUNT_BITS).contains(&err_bits),
            "err_bits = {err_bits} out of range 1..={}",
            regmap::ERR_COUNT_BITS
        );
        Self {
            width,
            err_bits,
            features: CounterFeatures::ALL,
        }
    }

    /// The same parameters with the channel built with `features`.
    pub fn with_features(self, features: CounterFeatures) -> Self {
        Self { features, ..self }
    }

    /// 2^W − 1: the mask of a W-bit register.
    pub fn count_mask(&self) -> u32 {
        mask_bits(self.width)
    }

    /// 2^E − 1: where the error counter saturates.
    pub fn err_max(&self) -> u32 {
        mask_bits(self.err_bits)
    }
}

/// Mask of the low `bits` bits (`bits` = 0..=32).
pub fn mask_bits(bits: u32) -> u32 {
    if bits >= 32 {
        u32::MAX
    } else {
        (1u32 << bits) - 1
    }
}

/// `value mod 2^width`.
pub fn wrap(value: u32, width: u32) -> u32 {
    value & mask_bits(width)
}

/// Reads the low `width` bits of `value` as two's complement and sign-extends
/// them to 32 bits (how COUNT, INDEX and PRESET appear on the bus).
pub fn sign_extend(value: u32, width: u32) -> u32 {
    let shift = 32 - width;
    (((value << shift) as i32) >> shift) as u32
}

/// One bus cycle (spec "Register bus").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BusCycle {
    /// Word address; only the map's `address_bits` low bits reach the decoder.
    pub addr: u32,
    pub wdata: u32,
    pub we: bool,
    pub re: bool,
}

impl BusCycle {
    /// A write of `data` to `addr`.
    pub fn write(addr: u32, data: u32) -> Self {
        Self {
            addr,
            wdata: data,
            we: true,
            re: false,
        }
    }
    /// A read of `addr`.
    pub fn read(addr: u32) -> Self {
        Self {
            addr,
            wdata: 0,
            we: false,
            re: true,
        }
    }

    /// Whether this cycle writes register `name` of `block` (the address
    /// bits the block decodes).
    pub fn writes(&self, block: &regmap::Block, name: &str) -> bool {
        self.we && self.addr & mask_bits(block.address_bits) == block.register(name).offset
    }

    /// A read-write register's next value: the written data in its
    /// writable bits if this cycle writes it, else `old`.
    pub fn written(&self, block: &regmap::Block, name: &str, old: u32) -> u32 {
        if self.writes(block, name) {
            self.wdata & block.register(name).writable_mask()
        } else {
            old
        }
    }

    /// The bits a write of 1 clears in write-1-to-clear register `name`
    /// (0 if this cycle does not write it).
    pub fn cleared(&self, block: &regmap::Block, name: &str) -> u32 {
        if self.writes(block, name) {
            self.wdata
        } else {
            0
        }
    }
}
