//! The suite's scales (`motionhdl_testbench::scale`): every check's
//! default-scale size stays at or above the floor it states, the long
//! scale is never smaller, and docs/testing.md states the table as it is.

use motionhdl_testbench::scale::{self, KNOBS};

#[test]
fn every_default_size_is_at_or_above_its_floor_and_the_long_one_above_it() {
    let mut names: Vec<&str> = KNOBS.iter().map(|k| k.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), KNOBS.len(), "knob names are unique");
    for k in KNOBS {
        assert!(
            k.default >= k.floor,
            "{} ({}): default {} {} is below its floor {}",
            k.name,
            k.check,
            k.default,
            k.unit,
            k.floor
        );
        assert!(
            k.long >= k.default,
            "{}: long {} below default {}",
            k.name,
            k.long,
            k.default
        );
        assert!(k.floor > 0, "{}: a floor of 0 states nothing", k.name);
        assert_eq!(scale::at(k.name, false), k.default);
        assert_eq!(scale::at(k.name, true), k.long);
    }
    // A knob removed is a check no longer sized by the scale: its table
    // row and this count go together.
    assert_eq!(KNOBS.len(), 14, "{} knobs", KNOBS.len());
}

/// The row docs/testing.md gives a knob.
fn row(k: &scale::Knob) -> String {
    format!(
        "| `{}` | {} | {} | {} | {} | {} |",
        k.name,
        k.check,
        k.unit,
        group(k.default),
        group(k.long),
        group(k.floor)
    )
}

/// `1234567` as `1 234 567`, as the docs write numbers.
fn group(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

#[test]
fn docs_testing_md_states_every_knob_as_the_table_has_it() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/testing.md"))
        .expect("docs/testing.md");
    let rows: Vec<&str> = doc.lines().filter(|l| l.starts_with("| `")).collect();
    let want: Vec<String> = KNOBS.iter().map(row).collect();
    assert_eq!(
        rows,
        want,
        "docs/testing.md's knob table must be exactly:\n{}",
        want.join("\n")
    );
}

#[test]
fn an_unknown_knob_panics_naming_it() {
    let e = std::panic::catch_unwind(|| scale::cases("no_such_knob")).unwrap_err();
    let msg = e.downcast_ref::<String>().cloned().unwrap_or_default();
    assert!(msg.contains("`no_such_knob`"), "{msg}");
}

#[test]
fn the_scale_follows_motionhdl_long() {
    // The variable as this run has it: scripts/test --long sets it.
    let set = std::env::var_os(scale::LONG_VAR).is_some_and(|v| !v.is_empty() && v != "0");
    assert_eq!(scale::long(), set);
    assert_eq!(scale::name(), if set { "long" } else { "default" });
}
