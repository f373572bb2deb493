//! The configuration file (TOML). Every key is optional; a missing key keeps
//! the built-in default. Unknown keys are errors, so a typo cannot silently
//! fall back to a default.
//!
//! ```toml
//! axes = 4              # 1..=16
//! counter_width = 28    # 8..=32 bits
//! clock_hz = 50_000_000 # 1 MHz..=400 MHz
//! isa_ram = "internal"  # or "external": where the ISA bridge's RAM lives
//! ```

use crate::CliError;
use motionhdl_model::{Config, IsaRam};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    axes: Option<i64>,
    counter_width: Option<i64>,
    clock_hz: Option<i64>,
    isa_ram: Option<String>,
}

/// Parses and range-checks a configuration file's text. `origin` names the
/// file in messages.
pub fn parse(text: &str, origin: &str) -> Result<Config, CliError> {
    let raw: RawConfig =
        toml::from_str(text).map_err(|e| CliError::input(format!("{origin}: {}", e.message())))?;
    let d = Config::default();
    let value = |name: &str, v: Option<i64>, default: u64| -> Result<u64, CliError> {
        match v {
            None => Ok(default),
            Some(v) if v >= 0 => Ok(v as u64),
            Some(v) => Err(CliError::input(format!(
                "{origin}: {name} = {v} is out of range: must not be negative"
            ))),
        }
    };
    let axes = value("axes", raw.axes, d.axes().into())?;
    let width = value("counter_width", raw.counter_width, d.counter_width().into())?;
    let clock = value("clock_hz", raw.clock_hz, d.clock_hz())?;
    let isa_ram = match raw.isa_ram.as_deref() {
        None => d.isa_ram(),
        Some(name) => IsaRam::from_name(name).ok_or_else(|| {
            CliError::input(format!(
                "{origin}: isa_ram = \"{name}\" is not allowed: use one of {}",
                IsaRam::NAMES.map(|n| format!("\"{n}\"")).join(", ")
            ))
        })?,
    };
    Config::new(axes, width, clock)
        .map(|c| c.with_isa_ram(isa_ram))
        .map_err(|e| CliError::input(format!("{origin}: {e}")))
}

/// Loads the configuration: the file if given, else the built-in default.
pub fn load(path: Option<&Path>) -> Result<Config, CliError> {
    match path {
        None => Ok(Config::default()),
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| {
                CliError::input(format!("cannot read config file {}: {e}", p.display()))
            })?;
            parse(&text, &p.display().to_string())
        }
    }
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
        assert!(e.message.contains("axes = -1"), "{}", e.message);
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
