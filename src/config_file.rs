//! The configuration file (TOML). Every key is optional; a missing key keeps
//! the built-in default. Unknown keys are errors, so a typo cannot silently
//! fall back to a default.
//!
//! ```toml
//! axes = 4              # 1..=16
//! counter_width = 28    # 8..=32 bits
//! clock_hz = 50_000_000 # 1 MHz..=400 MHz
//! isa_ram = "internal"  # or "external": where the ISA bridge's RAM lives
//! counter_filter = true    # counter channel build options
//! counter_index = true     # (docs/counter_bank.md, "Build options")
//! counter_error = true
//! counter_snapshot = true
//! input_filter_us = 1000   # 1..=50000: limit, home and alarm input filter
//! gpio_inputs = 16         # 0..=16 general-purpose inputs on the board's pins
//! gpio_outputs = 16        # 0..=16 general-purpose outputs on the board's pins
//! servo_dac = false        # the SERVO block: DAC pins, servo tick (needs isa_ram = "internal")
//! board = "ice40-hx8k"     # optional: the board must take every pin (else exit 2)
//! ```

use crate::CliError;
use motionhdl_model::{Config, CounterFeatures, IsaRam};
use serde::Deserialize;
use std::ops::RangeInclusive;
use std::path::Path;
use toml::{Spanned, Value};

/// The largest configuration file read: a real one is a few hundred bytes,
/// and `/dev/zero` must not be read for ever.
pub const MAX_BYTES: u64 = 1 << 20;

/// What a key accepts.
enum Kind {
    Integer(RangeInclusive<u64>),
    Choice(&'static [&'static str]),
    Boolean,
}

/// Every key, with what it accepts (messages name the allowed values).
const KEYS: [(&str, Kind); 13] = [
    ("axes", Kind::Integer(Config::AXES)),
    ("counter_width", Kind::Integer(Config::COUNTER_WIDTH)),
    ("clock_hz", Kind::Integer(Config::CLOCK_HZ)),
    ("isa_ram", Kind::Choice(&IsaRam::NAMES)),
    (CounterFeatures::KEYS[0], Kind::Boolean),
    (CounterFeatures::KEYS[1], Kind::Boolean),
    (CounterFeatures::KEYS[2], Kind::Boolean),
    (CounterFeatures::KEYS[3], Kind::Boolean),
    ("input_filter_us", Kind::Integer(Config::INPUT_FILTER_US)),
    ("gpio_inputs", Kind::Integer(Config::GPIO_INPUT_PINS)),
    ("gpio_outputs", Kind::Integer(Config::GPIO_OUTPUT_PINS)),
    ("servo_dac", Kind::Boolean),
    ("board", Kind::Choice(&crate::constraints::BOARD_NAMES)),
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    axes: Option<Spanned<Value>>,
    counter_width: Option<Spanned<Value>>,
    clock_hz: Option<Spanned<Value>>,
    isa_ram: Option<Spanned<Value>>,
    counter_filter: Option<Spanned<Value>>,
    counter_index: Option<Spanned<Value>>,
    counter_error: Option<Spanned<Value>>,
    counter_snapshot: Option<Spanned<Value>>,
    input_filter_us: Option<Spanned<Value>>,
    gpio_inputs: Option<Spanned<Value>>,
    gpio_outputs: Option<Spanned<Value>>,
    servo_dac: Option<Spanned<Value>>,
    board: Option<Spanned<Value>>,
}

fn kind(key: &str) -> &'static Kind {
    &KEYS.iter().find(|(k, _)| *k == key).expect("a known key").1
}

fn range_text(r: &RangeInclusive<u64>) -> String {
    format!("{}..={}", r.start(), r.end())
}

fn choices_text(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The message for `key = value` (as the user wrote it) that is not allowed.
fn refusal(origin: &str, key: &str, written: &str) -> CliError {
    CliError::input(match kind(key) {
        Kind::Integer(r) => format!(
            "{origin}: {key} = {written} is out of range: allowed {}",
            range_text(r)
        ),
        Kind::Choice(names) => format!(
            "{origin}: {key} = {written} is not allowed: use one of {}",
            choices_text(names)
        ),
        Kind::Boolean => format!("{origin}: {key} = {written} is not allowed: use true or false"),
    })
}

/// Parses and range-checks a configuration file's text. `origin` names the
/// file in messages.
pub fn parse(text: &str, origin: &str) -> Result<Config, CliError> {
    let raw: RawConfig = toml::from_str(text).map_err(|e| parse_error(text, origin, &e))?;
    let written = |v: &Spanned<Value>| text[v.span()].trim().to_string();
    let integer = |key: &str, v: &Option<Spanned<Value>>, default: u64| -> Result<u64, CliError> {
        let Some(v) = v else { return Ok(default) };
        let Kind::Integer(range) = kind(key) else {
            unreachable!("{key} is an integer key")
        };
        match v.get_ref() {
            Value::Integer(i) if u64::try_from(*i).is_ok_and(|u| range.contains(&u)) => {
                Ok(*i as u64)
            }
            Value::Integer(_) => Err(refusal(origin, key, &written(v))),
            _ => Err(CliError::input(format!(
                "{origin}: {key} = {} is not an integer: allowed {}",
                written(v),
                range_text(range)
            ))),
        }
    };
    let d = Config::default();
    let axes = integer("axes", &raw.axes, d.axes().into())?;
    let width = integer(
        "counter_width",
        &raw.counter_width,
        d.counter_width().into(),
    )?;
    let clock = integer("clock_hz", &raw.clock_hz, d.clock_hz())?;
    let filter_us = integer(
        "input_filter_us",
        &raw.input_filter_us,
        d.input_filter_us().into(),
    )?;
    let gpio_inputs = integer("gpio_inputs", &raw.gpio_inputs, d.gpio_inputs().into())?;
    let gpio_outputs = integer("gpio_outputs", &raw.gpio_outputs, d.gpio_outputs().into())?;
    let board = match &raw.board {
        None => None,
        Some(v) => Some(
            crate::constraints::BOARDS
                .into_iter()
                .find(|b| Some(b.name) == v.get_ref().as_str())
                .ok_or_else(|| refusal(origin, "board", &written(v)))?,
        ),
    };
    let isa_ram = match &raw.isa_ram {
        None => d.isa_ram(),
        Some(v) => v
            .get_ref()
            .as_str()
            .and_then(IsaRam::from_name)
            .ok_or_else(|| refusal(origin, "isa_ram", &written(v)))?,
    };
    let boolean = |key: &str, v: &Option<Spanned<Value>>| -> Result<bool, CliError> {
        match v {
            None => Ok(true),
            Some(v) => v
                .get_ref()
                .as_bool()
                .ok_or_else(|| refusal(origin, key, &written(v))),
        }
    };
    let [filter, index, error, snapshot] = CounterFeatures::KEYS;
    let features = CounterFeatures {
        filter: boolean(filter, &raw.counter_filter)?,
        index: boolean(index, &raw.counter_index)?,
        error: boolean(error, &raw.counter_error)?,
        snapshot: boolean(snapshot, &raw.counter_snapshot)?,
    };
    // Off unless given (the counter options are on unless given).
    let servo_dac = raw.servo_dac.is_some() && boolean("servo_dac", &raw.servo_dac)?;
    if servo_dac && isa_ram == IsaRam::External {
        return Err(CliError::input(format!(
            "{origin}: servo_dac = true needs isa_ram = \"internal\" (the servo \
             card's top has the shared RAM inside); with isa_ram = \"external\" \
             use servo_dac = false"
        )));
    }
    let config = Config::new(axes, width, clock)
        .and_then(|c| c.with_input_filter_us(filter_us))
        .and_then(|c| c.with_gpio_pins(gpio_inputs, gpio_outputs))
        .map(|c| {
            c.with_isa_ram(isa_ram)
                .with_counter_features(features)
                .with_servo_dac(servo_dac)
        })
        .map_err(|e| CliError::input(format!("{origin}: {e}")))?;
    if let Some(b) = board {
        check_fit(b, &config).map_err(|why| CliError::input(format!("{origin}: {why}")))?;
    }
    Ok(config)
}

/// Checks that `config`'s board ports fit `board`'s pins: `Err` says how
/// many it needs and has, and how many axes would fit.
fn check_fit(board: &crate::constraints::Board, config: &Config) -> Result<(), String> {
    let width = |ports: &[crate::board::BoardPort]| -> u32 { ports.iter().map(|p| p.width).sum() };
    let needed = |c: &Config| width(&crate::board::ports(c));
    let ports = crate::board::ports(config);
    let Err(why) = crate::constraints::assign(board, &ports) else {
        return Ok(());
    };
    // (Elaborating a top takes seconds: the configuration's is at hand.)
    let total = width(&ports);
    let one = config.with_axes(1).expect("1 axis is allowed");
    let fixed_and_one = needed(&one);
    let per_axis = needed(&one.with_axes(2).expect("2 axes are allowed")) - fixed_and_one;
    let fixed = fixed_and_one - per_axis;
    let room = (board.pool.len() as u32).saturating_sub(fixed) / per_axis;
    Err(format!(
        "board = \"{}\" has {} user pins; this configuration needs {total} \
         ({per_axis} per axis for axes = {}, {fixed} for the rest: clock, reset, FSMC, ISA, \
         e-stop, IRQ and gpio_inputs = {}, gpio_outputs = {}); at most {room} axes fit \
         with these settings ({why})",
        board.name,
        board.pool.len(),
        config.axes(),
        config.gpio_inputs(),
        config.gpio_outputs(),
    ))
}

/// A TOML error as the `toml` crate reports it (line, column, the text);
/// an integer too large for TOML itself is reported like any out-of-range
/// value, naming the key.
fn parse_error(text: &str, origin: &str, e: &toml::de::Error) -> CliError {
    if let Some(span) = e.span() {
        let line_start = text[..span.start].rfind('\n').map_or(0, |i| i + 1);
        let line = text[line_start..].lines().next().unwrap_or_default();
        if let Some((key, value)) = line.split_once('=') {
            let key = key.trim();
            let value = value.split('#').next().unwrap_or_default().trim();
            let digits: String = value.chars().filter(|&c| c != '_').collect();
            let decimal = digits.trim_start_matches(['+', '-']);
            let too_large = !decimal.is_empty()
                && decimal.bytes().all(|b| b.is_ascii_digit())
                && digits.parse::<i64>().is_err();
            let integer_key = matches!(
                KEYS.iter().find(|(k, _)| *k == key),
                Some((_, Kind::Integer(_)))
            );
            if too_large && integer_key {
                return refusal(origin, key, value);
            }
        }
    }
    CliError::input(format!("{origin}: {}", e.to_string().trim_end()))
}

/// Loads the configuration: the file if given, else the built-in default.
pub fn load(path: Option<&Path>) -> Result<Config, CliError> {
    let Some(p) = path else {
        return Ok(Config::default());
    };
    let cannot =
        |why: String| CliError::input(format!("cannot read config file {}: {why}", p.display()));
    if p.is_dir() {
        return Err(cannot("it is a directory".into()));
    }
    let data = crate::output::read_bounded(p, MAX_BYTES)
        .map_err(|e| cannot(e.to_string()))?
        .map_err(|limit| {
            cannot(format!(
                "it is larger than {} MiB, the most a configuration file may be",
                limit >> 20
            ))
        })?;
    let text = String::from_utf8(data).map_err(|e| {
        cannot(format!(
            "it is not UTF-8 text (byte {} is not)",
            e.utf8_error().valid_up_to()
        ))
    })?;
    parse(&text, &p.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isa_ram_is_read_and_checked() {
        let c = parse("isa_ram = \"external\"\n", "t").unwrap();
        assert_eq!(c.isa_ram(), IsaRam::External);
        let e = parse("isa_ram = \"sram\"\n", "t").unwrap_err().to_string();
        assert!(e.contains("isa_ram = \"sram\""), "{e}");
        assert!(e.contains("\"internal\", \"external\""), "{e}");
    }

    #[test]
    fn servo_dac_is_read_and_checked() {
        assert!(!parse("", "t").unwrap().servo_dac());
        assert!(parse("servo_dac = true\n", "t").unwrap().servo_dac());
        let e = parse("servo_dac = 1\n", "t").unwrap_err().to_string();
        assert!(
            e.contains("servo_dac = 1 is not allowed: use true or false"),
            "{e}"
        );
        let e = parse("servo_dac = true\nisa_ram = \"external\"\n", "t")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("servo_dac = true needs isa_ram = \"internal\""),
            "{e}"
        );
        let c = parse("servo_dac = false\nisa_ram = \"external\"\n", "t").unwrap();
        assert!(!c.servo_dac());
    }

    #[test]
    fn counter_features_are_read_and_checked() {
        let c = parse("counter_index = false\ncounter_error = false\n", "t").unwrap();
        let f = c.counter_features();
        assert!(f.filter && !f.index && !f.error && f.snapshot, "{f:?}");
        let e = parse("counter_snapshot = 1\n", "c").unwrap_err();
        assert_eq!(e.exit_code, 2);
        assert_eq!(
            e.message,
            "c: counter_snapshot = 1 is not allowed: use true or false"
        );
    }

    #[test]
    fn empty_file_is_the_default() {
        assert_eq!(parse("", "t").unwrap(), Config::default());
    }

    #[test]
    fn values_are_read() {
        let c = parse(
            "axes = 8\ncounter_width = 32\nclock_hz = 100_000_000\n",
            "t",
        )
        .unwrap();
        assert_eq!(
            (c.axes(), c.counter_width(), c.clock_hz()),
            (8, 32, 100_000_000)
        );
    }

    #[test]
    fn out_of_range_names_value_and_range() {
        let e = parse("axes = 0", "cfg.toml").unwrap_err();
        assert_eq!(e.exit_code, 2);
        assert_eq!(
            e.message,
            "cfg.toml: axes = 0 is out of range: allowed 1..=16"
        );
        let e = parse("counter_width = 33", "c").unwrap_err();
        assert_eq!(
            e.message,
            "c: counter_width = 33 is out of range: allowed 8..=32"
        );
        let e = parse("axes = -1", "c").unwrap_err();
        assert_eq!(e.message, "c: axes = -1 is out of range: allowed 1..=16");
        let e = parse("input_filter_us = 50001", "c").unwrap_err();
        assert_eq!(e.exit_code, 2);
        assert_eq!(
            e.message,
            "c: input_filter_us = 50001 is out of range: allowed 1..=50000"
        );
        let c = parse("input_filter_us = 2\nclock_hz = 10_000_000", "c").unwrap();
        assert_eq!((c.input_filter_us(), c.filter_tick_clocks()), (2, 5));
    }

    #[test]
    fn a_board_too_small_for_the_pins_is_refused_with_the_numbers() {
        let e = parse("board = \"cyclone4-de0nano\"\naxes = 2", "c").unwrap_err();
        assert_eq!(e.exit_code, 2);
        assert!(
            e.message.starts_with(
                "c: board = \"cyclone4-de0nano\" has 100 user pins; this configuration needs 127 (10 per axis for axes = 2, 107 for the rest"
            ),
            "{}",
            e.message
        );
        assert!(e.message.contains("at most 0 axes fit"), "{}", e.message);
        // Without the general-purpose I/O two axes fit; the HX8K takes the default.
        parse(
            "board = \"cyclone4-de0nano\"\naxes = 2\ngpio_inputs = 0\ngpio_outputs = 0",
            "c",
        )
        .unwrap();
        parse("board = \"ice40-hx8k\"", "c").unwrap();
        let e = parse("board = \"de0\"", "c").unwrap_err();
        assert!(
            e.message
                .contains("\"ice40-hx8k\", \"ecp5-25k\", \"cyclone4-de0nano\""),
            "{}",
            e.message
        );
        let e = parse("gpio_outputs = 17", "c").unwrap_err();
        assert_eq!(
            e.message,
            "c: gpio_outputs = 17 is out of range: allowed 0..=16"
        );
    }

    #[test]
    fn unknown_keys_and_bad_types_are_errors() {
        let e = parse("axis = 4", "c").unwrap_err();
        assert!(e.message.contains("axis"), "{}", e.message);
        assert_eq!(e.exit_code, 2);
        let e = parse("axes = \"four\"", "c").unwrap_err();
        assert_eq!(e.exit_code, 2);
    }
}
