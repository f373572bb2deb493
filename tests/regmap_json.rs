//! `regmap.json`, the machine-readable register map, parsed back with
//! serde_json and compared with the table (the read-back itself is
//! `common::regmap::check_json`, which tests/regmap_svd.rs runs too).

mod common;

use common::regmap::{check_json, default_map, other_configs};
use motionhdl_model::regmap::mcu_map;

#[test]
fn json_parses_back_to_the_table() {
    assert_eq!(check_json(&default_map()), 140 + 1024);
    for c in other_configs() {
        check_json(&mcu_map(&c));
    }
}
