//! Checks of the register map as a whole: addresses, fields and the ID block.

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
        4 | (28 << 8) | (ERR_COUNT_BITS << 16) | (0xf << 24)
    );
    // The DSP seed set: snapshot only, no error counter.
    let lean = counter_bank_with(4, 28, crate::CounterFeatures::from_bits(8));
    assert_eq!(lean.register("INFO").reset, 4 | (28 << 8) | (8 << 24));
    assert_eq!(lean.array("CH").register("CTRL").writable_mask(), 0x0f);
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
