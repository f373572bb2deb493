//! Build-time configuration of the gateware: axis count, counter width, clock.

use crate::safety_io::{
    filter_tick_clocks, DEFAULT_INPUT_FILTER_US, GPIO_INPUTS, GPIO_OUTPUTS, INPUT_FILTER_US,
};
use std::fmt;
use std::ops::RangeInclusive;

/// Gateware configuration. Construct with [`Config::new`] so that every value
/// is checked; [`Config::default`] is the built-in default (4 axes, 28-bit
/// counters, 50 MHz).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    axes: u32,
    counter_width: u32,
    clock_hz: u64,
    isa_ram: IsaRam,
    counter_features: CounterFeatures,
    input_filter_us: u32,
    /// General-purpose (inputs, outputs) the board wrapper brings to pins.
    gpio_pins: (u32, u32),
    /// The SERVO block (docs/servo_dac.md) in the top: the DAC pins, the
    /// servo tick as the counters' snapshot and an interrupt cause.
    servo_dac: bool,
}

/// The counter channel's optional features (docs/counter_bank.md, "Build
/// options"). A feature left out has no registers, fields or logic: its
/// fields are absent from the register map (writes to them are ignored and
/// they read 0) and INFO says which features the build has. All are in by
/// default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CounterFeatures {
    /// The programmable digital filter on A, B and Z (CTRL.FILTER_AB/_Z).
    pub filter: bool,
    /// The index input: latch, clear, gate, one-shot (INDEX register).
    pub index: bool,
    /// Illegal-transition detection: STATUS.ERR and ERR_COUNT, CTRL.ERR_EN.
    pub error: bool,
    /// SNAPSHOT: COUNT, INDEX and STATUS read as captured together; without
    /// it they read live.
    pub snapshot: bool,
}

impl Default for CounterFeatures {
    fn default() -> Self {
        Self::ALL
    }
}

impl CounterFeatures {
    /// Every feature in: the default build.
    pub const ALL: Self = Self {
        filter: true,
        index: true,
        error: true,
        snapshot: true,
    };
    /// The configuration-file keys, in INFO's bit order.
    pub const KEYS: [&'static str; 4] = [
        "counter_filter",
        "counter_index",
        "counter_error",
        "counter_snapshot",
    ];

    /// The features as bits, in the order of [`Self::KEYS`].
    pub fn bits(self) -> u32 {
        u32::from(self.filter)
            | u32::from(self.index) << 1
            | u32::from(self.error) << 2
            | u32::from(self.snapshot) << 3
    }

    /// The features whose bits are set in `bits` (order of [`Self::KEYS`]).
    pub fn from_bits(bits: u32) -> Self {
        Self {
            filter: bits & 1 != 0,
            index: bits & 2 != 0,
            error: bits & 4 != 0,
            snapshot: bits & 8 != 0,
        }
    }

    /// Every combination, the full build first.
    pub fn every() -> impl Iterator<Item = Self> {
        (0..16).rev().map(Self::from_bits)
    }
}

/// Where the ISA bridge's shared 1 K × 16 RAM lives (a build option).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IsaRam {
    /// Block RAM inside the FPGA, with a synchronous DSP port.
    #[default]
    Internal,
    /// An external dual-port SRAM; the FPGA drives its PC-side port.
    External,
}

impl IsaRam {
    /// The configuration-file spellings.
    pub const NAMES: [&'static str; 2] = ["internal", "external"];

    pub fn name(self) -> &'static str {
        match self {
            IsaRam::Internal => "internal",
            IsaRam::External => "external",
        }
    }

    /// Parses a configuration-file value.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "internal" => Some(IsaRam::Internal),
            "external" => Some(IsaRam::External),
            _ => None,
        }
    }
}

impl Config {
    /// Axes the counter bank and pulse generators can be built for.
    pub const AXES: RangeInclusive<u64> = 1..=16;
    /// Counter widths in bits. Below 8 a counter wraps too fast to be useful;
    /// above 32 a count no longer fits one 32-bit firmware read.
    pub const COUNTER_WIDTH: RangeInclusive<u64> = 8..=32;
    /// FPGA clock frequencies in Hz that the timing constraints cover.
    pub const CLOCK_HZ: RangeInclusive<u64> = 1_000_000..=400_000_000;
    /// Filter times of the machine inputs (limits, home, alarm), in µs.
    pub const INPUT_FILTER_US: RangeInclusive<u64> = INPUT_FILTER_US;
    /// General-purpose inputs the board wrapper brings to pins (the core
    /// always has GPIO_INPUTS; the rest read 0).
    pub const GPIO_INPUT_PINS: RangeInclusive<u64> = 0..=GPIO_INPUTS as u64;
    /// General-purpose outputs the board wrapper brings to pins.
    pub const GPIO_OUTPUT_PINS: RangeInclusive<u64> = 0..=GPIO_OUTPUTS as u64;

    /// Checks every value against its allowed range.
    pub fn new(axes: u64, counter_width: u64, clock_hz: u64) -> Result<Self, ConfigError> {
        check("axes", axes, Self::AXES)?;
        check("counter_width", counter_width, Self::COUNTER_WIDTH)?;
        check("clock_hz", clock_hz, Self::CLOCK_HZ)?;
        Ok(Self {
            axes: axes as u32,
            counter_width: counter_width as u32,
            clock_hz,
            isa_ram: IsaRam::default(),
            counter_features: CounterFeatures::ALL,
            input_filter_us: DEFAULT_INPUT_FILTER_US as u32,
            gpio_pins: (GPIO_INPUTS, GPIO_OUTPUTS),
            servo_dac: false,
        })
    }

    /// The same configuration with the machine inputs' filter time set to
    /// `us` microseconds (checked against [`Self::INPUT_FILTER_US`]).
    pub fn with_input_filter_us(self, us: u64) -> Result<Self, ConfigError> {
        check("input_filter_us", us, Self::INPUT_FILTER_US)?;
        Ok(Self {
            input_filter_us: us as u32,
            ..self
        })
    }

    /// The same configuration with `inputs` general-purpose inputs and
    /// `outputs` outputs on the board's pins (checked against
    /// [`Self::GPIO_INPUT_PINS`] and [`Self::GPIO_OUTPUT_PINS`]): the first
    /// ones of the core's; a board with few pins leaves the rest out.
    pub fn with_gpio_pins(self, inputs: u64, outputs: u64) -> Result<Self, ConfigError> {
        check("gpio_inputs", inputs, Self::GPIO_INPUT_PINS)?;
        check("gpio_outputs", outputs, Self::GPIO_OUTPUT_PINS)?;
        Ok(Self {
            gpio_pins: (inputs as u32, outputs as u32),
            ..self
        })
    }

    /// General-purpose inputs on the board's pins.
    pub fn gpio_inputs(&self) -> u32 {
        self.gpio_pins.0
    }

    /// General-purpose outputs on the board's pins.
    pub fn gpio_outputs(&self) -> u32 {
        self.gpio_pins.1
    }

    /// The machine inputs' filter time in microseconds.
    pub fn input_filter_us(&self) -> u32 {
        self.input_filter_us
    }

    /// The machine inputs' filter tick in clocks (docs/safety_io.md).
    pub fn filter_tick_clocks(&self) -> u32 {
        filter_tick_clocks(u64::from(self.input_filter_us), self.clock_hz)
    }

    /// The same configuration with `axes` axes (checked), every other
    /// setting kept.
    pub fn with_axes(self, axes: u64) -> Result<Self, ConfigError> {
        check("axes", axes, Self::AXES)?;
        Ok(Self {
            axes: axes as u32,
            ..self
        })
    }

    /// The same configuration with the ISA bridge's RAM at `isa_ram`.
    pub fn with_isa_ram(self, isa_ram: IsaRam) -> Self {
        Self { isa_ram, ..self }
    }

    pub fn isa_ram(&self) -> IsaRam {
        self.isa_ram
    }

    /// The same configuration with the counter channels built with `features`.
    pub fn with_counter_features(self, counter_features: CounterFeatures) -> Self {
        Self {
            counter_features,
            ..self
        }
    }

    pub fn counter_features(&self) -> CounterFeatures {
        self.counter_features
    }

    /// The same configuration with the SERVO block (the DAC output and the
    /// servo tick) in the top, or without it. The servo card's top has the
    /// shared RAM inside (the configuration file refuses `isa_ram =
    /// "external"` with it; the top's constructor panics).
    pub fn with_servo_dac(self, servo_dac: bool) -> Self {
        Self { servo_dac, ..self }
    }

    /// The top has the SERVO block.
    pub fn servo_dac(&self) -> bool {
        self.servo_dac
    }

    pub fn axes(&self) -> u32 {
        self.axes
    }
    pub fn counter_width(&self) -> u32 {
        self.counter_width
    }
    pub fn clock_hz(&self) -> u64 {
        self.clock_hz
    }
    /// Clock period in picoseconds, rounded to the nearest picosecond.
    pub fn clock_period_ps(&self) -> u64 {
        (1_000_000_000_000 + self.clock_hz / 2) / self.clock_hz
    }
}

impl Default for Config {
    fn default() -> Self {
        Self {
            axes: 4,
            counter_width: 28,
            clock_hz: 50_000_000,
            isa_ram: IsaRam::Internal,
            counter_features: CounterFeatures::ALL,
            input_filter_us: DEFAULT_INPUT_FILTER_US as u32,
            gpio_pins: (GPIO_INPUTS, GPIO_OUTPUTS),
            servo_dac: false,
        }
    }
}

fn check(name: &'static str, value: u64, range: RangeInclusive<u64>) -> Result<(), ConfigError> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(ConfigError::OutOfRange {
            name,
            value,
            min: *range.start(),
            max: *range.end(),
        })
    }
}

/// A configuration value outside its allowed range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ConfigError {
    OutOfRange {
        name: &'static str,
        value: u64,
        min: u64,
        max: u64,
    },
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfigError::OutOfRange {
                name,
                value,
                min,
                max,
            } => write!(f, "{name} = {value} is out of range: allowed {min}..={max}"),
        }
    }
}

impl std::error::Error for ConfigError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_valid_and_matches_the_seed_card() {
        let d = Config::default();
        assert_eq!(Config::new(4, 28, 50_000_000), Ok(d));
        assert_eq!(d.clock_period_ps(), 20_000);
    }

    #[test]
    fn every_bound_is_enforced_and_named() {
        for (axes, width, clk, name, value) in [
            (0, 28, 50_000_000, "axes", 0),
            (17, 28, 50_000_000, "axes", 17),
            (4, 0, 50_000_000, "counter_width", 0),
            (4, 7, 50_000_000, "counter_width", 7),
            (4, 33, 50_000_000, "counter_width", 33),
            (4, 28, 0, "clock_hz", 0),
            (4, 28, 400_000_001, "clock_hz", 400_000_001),
        ] {
            let err = Config::new(axes, width, clk).unwrap_err();
            let msg = err.to_string();
            assert!(msg.starts_with(&format!("{name} = {value} ")), "{msg}");
            assert!(msg.contains("allowed"), "{msg}");
        }
        assert!(Config::new(1, 8, 1_000_000).is_ok());
        assert!(Config::new(16, 32, 400_000_000).is_ok());
        let d = Config::default();
        for us in [0, 50_001] {
            let msg = d.with_input_filter_us(us).unwrap_err().to_string();
            assert_eq!(
                msg,
                format!("input_filter_us = {us} is out of range: allowed 1..=50000")
            );
        }
        assert_eq!(d.with_input_filter_us(1).unwrap().input_filter_us(), 1);
    }

    #[test]
    fn counter_features_round_trip_through_their_bits() {
        let all: Vec<_> = CounterFeatures::every().collect();
        assert_eq!(all.len(), 16);
        assert_eq!(all[0], CounterFeatures::ALL);
        for (i, f) in all.iter().enumerate() {
            assert_eq!(CounterFeatures::from_bits(f.bits()), *f);
            assert_eq!(f.bits(), 15 - i as u32);
        }
        assert_eq!(Config::default().counter_features(), CounterFeatures::ALL);
    }
}
