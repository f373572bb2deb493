//! The ISA bridge's C header, `motionhdl_isa.h`: the numbers it must
//! define, from the register map, for the tests of `tests/isa_header.rs`
//! and `tests/isa_header_c.rs`.

use motionhdl_model::isa_bridge as card;
use motionhdl_model::regmap::{self, ISA_ADDR_BITS, ISA_RAM_WORDS};

pub const P: &str = "MOTIONHDL_ISA";

/// Every number the header must define, by name, from the register map
/// (and the model's port decode), following the header's naming scheme.
pub fn expected() -> Vec<(String, u64)> {
    let map = regmap::isa_bridge();
    let mut v = vec![
        (format!("{P}_RAM_WORDS"), u64::from(ISA_RAM_WORDS)),
        (format!("{P}_ADDR_BITS"), u64::from(ISA_ADDR_BITS)),
        (format!("{P}_PORT_COUNT"), 1u64 << map.address_bits),
        (
            format!("{P}_BASE_PORT_MAX"),
            u64::from(card::port(u8::MAX, 0)),
        ),
    ];
    for r in &map.registers {
        v.push((format!("{P}_{}_OFFSET", r.name), u64::from(r.offset)));
        v.push((format!("{P}_{}_reset", r.name), u64::from(r.reset)));
        for f in &r.fields {
            let n = format!("{P}_{}__{}", r.name, f.name);
            v.push((format!("{n}_bm"), u64::from(f.mask())));
            v.push((format!("{n}_bp"), u64::from(f.lsb)));
            v.push((format!("{n}_bw"), u64::from(f.width)));
            v.push((format!("{n}_reset"), u64::from(f.reset)));
        }
    }
    v
}
