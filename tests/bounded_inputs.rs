//! Every argument and configuration key is bounded and reported in the
//! user's words: exit code 2, the key, the value and what is allowed, and
//! nothing written.

mod common;

use common::fs_state::{assert_refused, names, run};
use std::fs;

/// Runs `generate` with `text` as the configuration; asserts exit 2,
/// every needle, and that nothing but the config file exists afterwards.
fn refused_config(text: &str, needles: &[&str]) {
    let t = tempfile::tempdir().unwrap();
    fs::write(t.path().join("c.toml"), text).unwrap();
    let o = run(
        t.path(),
        &["generate", "--out", "gen", "--config", "c.toml"],
    );
    assert_refused(&o, 2, needles);
    assert_eq!(
        names(t.path()),
        ["c.toml"],
        "{text:?}: something was written"
    );
}

#[test]
fn endless_config_files_are_cut_off_at_one_mebibyte() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        let t = tempfile::tempdir().unwrap();
        let o = run(t.path(), &["generate", "--out", "gen", "--config", dev]);
        assert_refused(
            &o,
            2,
            &[&format!(
                "cannot read config file {dev}: it is larger than 1 MiB"
            )],
        );
        assert!(names(t.path()).is_empty());
    }
}

#[test]
fn a_config_that_is_not_text_or_not_a_file_is_refused() {
    refused_config("axes = 4\n\u{0}\u{ff}", &["c.toml"]);
    let mut bytes = b"axes = 4\n".to_vec();
    bytes.push(0xff);
    let t = tempfile::tempdir().unwrap();
    fs::write(t.path().join("c.toml"), bytes).unwrap();
    let o = run(
        t.path(),
        &["generate", "--out", "gen", "--config", "c.toml"],
    );
    assert_refused(&o, 2, &["it is not UTF-8 text (byte 9 is not)"]);
    let o = run(t.path(), &["generate", "--out", "gen", "--config", "."]);
    assert_refused(&o, 2, &["cannot read config file .: it is a directory"]);
}

#[test]
fn malformed_toml_reports_line_column_and_the_text() {
    refused_config(
        "# a comment\naxes = [\n",
        &[
            "c.toml: TOML parse error at line 2, column 10",
            "2 | axes = [",
            "invalid array",
        ],
    );
}

#[test]
fn a_number_too_large_for_toml_names_the_key_and_range() {
    refused_config(
        "axes = 99999999999999999999 # many\n",
        &["c.toml: axes = 99999999999999999999 is out of range: allowed 1..=16"],
    );
    refused_config(
        "clock_hz = -99999999999999999999\n",
        &["clock_hz = -99999999999999999999 is out of range: allowed 1000000..=400000000"],
    );
}

#[test]
fn a_value_of_the_wrong_type_names_the_key_and_range() {
    for (text, needle) in [
        (
            "axes = \"4\"\n",
            "c.toml: axes = \"4\" is not an integer: allowed 1..=16",
        ),
        (
            "counter_width = 28.0\n",
            "counter_width = 28.0 is not an integer: allowed 8..=32",
        ),
        (
            "clock_hz = true\n",
            "clock_hz = true is not an integer: allowed 1000000..=400000000",
        ),
        (
            "isa_ram = 5\n",
            "isa_ram = 5 is not allowed: use one of \"internal\", \"external\"",
        ),
        ("axes = -3\n", "axes = -3 is out of range: allowed 1..=16"),
        (
            "axes = 1_000\n",
            "axes = 1_000 is out of range: allowed 1..=16",
        ),
    ] {
        refused_config(text, &[needle]);
    }
}

#[test]
fn unknown_and_repeated_keys_are_refused_with_their_place() {
    refused_config("axis = 4\n", &["line 1, column 1", "unknown field `axis`"]);
    refused_config("axes = 4\naxes = 5\n", &["line 2", "duplicate key"]);
}

#[test]
fn counts_and_seeds_out_of_range_are_refused_before_any_work() {
    let t = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (
            vec!["bench", "--cycles", "18446744073709551615"],
            "18446744073709551615 is not in 1..=100000000",
        ),
        (vec!["bench", "--cycles", "0"], "0 is not in 1..=100000000"),
        (vec!["bench", "--cycles", "-1"], "unexpected argument '-1'"),
        (
            vec!["synth", "--seed", "2147483648"],
            "2147483648 is not in 0..=2147483647",
        ),
        (
            vec!["synth", "--target", "gowin"],
            "--target gowin is not known: use one of ice40-hx8k, ecp5-25k",
        ),
        (
            vec!["generate", "--out", ""],
            "a value is required for '--out <OUT>'",
        ),
        (
            vec!["trace", "no_such", "--out", "x.vcd"],
            "unknown scenario `no_such`",
        ),
    ] {
        let o = run(t.path(), &args);
        assert_refused(&o, 2, &[needle]);
    }
    assert!(names(t.path()).is_empty());
}
