//! `regmap.json`, the machine-readable register map, parsed back with
//! serde_json and compared with the table (the read-back itself is
//! `common::regmap::check_json`, which tests/regmap_svd.rs runs too), and
//! validated against `regmap.schema.json` by a JSON Schema validator.

mod common;

use common::regmap::{check_json, default_map, other_configs};
use motionhdl::regmap_export::json;
use motionhdl_model::regmap::mcu_map;
use serde_json::{json as value, Value};

#[test]
fn json_parses_back_to_the_table() {
    assert_eq!(check_json(&default_map()), 140 + 1024);
    for c in other_configs() {
        check_json(&mcu_map(&c));
    }
}

#[test]
fn json_follows_its_schema_and_a_broken_copy_does_not() {
    let schema: Value = serde_json::from_str(&json::schema()).expect("the schema is JSON");
    assert_eq!(
        schema["$schema"],
        "https://json-schema.org/draft/2020-12/schema"
    );
    let validator = jsonschema::validator_for(&schema).expect("a valid JSON Schema");
    let mut maps = vec![default_map()];
    maps.extend(other_configs().iter().map(mcu_map));
    for map in &maps {
        let v: Value = serde_json::from_str(&json::json(map)).unwrap();
        assert_eq!(v["$schema"], json::SCHEMA_FILE_NAME);
        assert_eq!(v["format_version"], json::FORMAT_VERSION);
        let errors: Vec<String> = validator.iter_errors(&v).map(|e| e.to_string()).collect();
        assert!(errors.is_empty(), "{}: {errors:?}", map.description);
    }
    // Each breakage is caught: a key gone, a key unknown (at the top and
    // in a field), a number of the wrong type, a place with no offset.
    let good: Value = serde_json::from_str(&json::json(&maps[0])).unwrap();
    type Breakage = (&'static str, fn(&mut Value));
    let breakages: [Breakage; 5] = [
        ("no map_hash", |v| {
            v.as_object_mut().unwrap().remove("map_hash");
        }),
        ("unknown top key", |v| v["mystery"] = value!(1)),
        ("unknown field key", |v| {
            v["blocks"][0]["registers"][0]["fields"][0]["msb"] = value!(31)
        }),
        ("lsb a string", |v| {
            v["blocks"][0]["registers"][0]["fields"][0]["lsb"] = value!("0")
        }),
        ("register without a place", |v| {
            v["blocks"][0]["registers"][0]
                .as_object_mut()
                .unwrap()
                .remove("byte_offset");
        }),
    ];
    for (what, break_it) in breakages {
        let mut v = good.clone();
        break_it(&mut v);
        assert!(!validator.is_valid(&v), "{what}: still valid");
    }
    assert!(validator.is_valid(&good));
}
