//! The exported Verilog modules: one entry per `generated/verilog/*.v` file.

use crate::ports::Port;
use crate::{
    banner, verilog, CounterBank, FsmcBridge, IsaBridge, IsaBridgeExternal, Ls153, Ls688,
    MotionController, MotionControllerExternal, MotionControllerServo, PulseGenerator,
    PulseModeSelector, PulseModeSelectorRegistered, QuadratureCore, SafetyIo,
};
use motionhdl_spec::{Config, CounterFeatures, IsaRam};
use rust_hdl::prelude::Block;

/// One exported module.
#[derive(Clone, Debug)]
pub struct VerilogModule {
    /// Module name, also the file stem.
    pub name: &'static str,
    /// What the module is, for the file banner.
    pub summary: &'static str,
    /// Its ports in declaration order, from the rust-hdl block itself.
    pub ports: Vec<Port>,
    /// The Verilog text.
    pub text: String,
}

fn module<B: Block>(mut uut: B, name: &'static str, summary: &'static str) -> VerilogModule {
    uut.connect_all();
    let text = verilog::export(
        &uut,
        name,
        &[
            banner(),
            format!("{name}: {summary}"),
            "Flattened from the rust-hdl description in motionhdl-hdl; one module per file.".into(),
        ],
    );
    VerilogModule {
        name,
        summary,
        ports: crate::ports::ports(&uut),
        text,
    }
}

/// The 74LS153 dual 4-to-1 data selector.
pub fn ls153() -> VerilogModule {
    module(
        Ls153::default(),
        "ls153",
        "74LS153 dual 4-to-1 data selector, one port per chip pin (combinational)",
    )
}

/// The 74LS688 8-bit identity comparator.
pub fn ls688() -> VerilogModule {
    module(
        Ls688::default(),
        "ls688",
        "74LS688 8-bit identity comparator: P=Q output active low, G enable active low (combinational)",
    )
}

/// The combinational pulse-mode selector.
pub fn pulse_mode_selector() -> VerilogModule {
    module(
        PulseModeSelector::default(),
        "pulse_mode_selector",
        "command-pulse mode selector, K=0 pulse+direction, K=1 CW/CCW, one 74LS153 (combinational)",
    )
}

/// The registered pulse-mode selector, for output pins.
pub fn pulse_mode_selector_registered() -> VerilogModule {
    module(
        PulseModeSelectorRegistered::default(),
        "pulse_mode_selector_registered",
        "pulse-mode selector with registered, glitch-free outputs (one clock latency, synchronous reset)",
    )
}

/// The counter bank for `axes` channels (1..=16) of `width`-bit counters
/// with every feature.
pub fn counter_bank(axes: u32, width: u32) -> VerilogModule {
    counter_bank_with(axes, width, CounterFeatures::ALL)
}

/// The counter bank built with `features` (docs/counter_bank.md, "Build
/// options").
pub fn counter_bank_with(axes: u32, width: u32, features: CounterFeatures) -> VerilogModule {
    const SUMMARY: &str = "quadrature/pulse counter bank: X4/X2/X1, pulse+direction, CW/CCW; \
                           filters, index, snapshot, register bus (docs/counter_bank.md)";
    // The axis count sets port widths, a compile-time parameter in rust-hdl.
    macro_rules! bank {
        ($($n:literal)+) => {
            match axes {
                $($n => module(
                    CounterBank::<$n>::with_features(width, features),
                    "counter_bank",
                    SUMMARY,
                ),)+
                _ => panic!("axes = {axes} out of range 1..=16"),
            }
        };
    }
    bank!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// The ×4 decoder and counter alone, `width` bits (2..=32).
pub fn quadrature_core(width: u32) -> VerilogModule {
    module(
        QuadratureCore::new(width),
        "quadrature_core",
        "X4 quadrature decoder and up/down counter alone: synchronisers, no filter, index or bus",
    )
}

/// The ISA address-counter interface, module `isa_bridge`, with its shared
/// RAM inside the FPGA or as an external dual-port SRAM (the ports differ).
pub fn isa_bridge(ram: IsaRam) -> VerilogModule {
    match ram {
        IsaRam::Internal => module(
            IsaBridge::new(),
            "isa_bridge",
            "ISA address-counter interface: 74LS688 decode, DATA/ADDR_CLEAR/ADDR_INC/STATUS, \
             1 K x 16 shared RAM in block RAM with a DSP port (docs/isa_bridge.md)",
        ),
        IsaRam::External => module(
            IsaBridgeExternal::new(),
            "isa_bridge",
            "ISA address-counter interface: 74LS688 decode, DATA/ADDR_CLEAR/ADDR_INC/STATUS, \
             PC-side port of an external 1 K x 16 dual-port SRAM (docs/isa_bridge.md)",
        ),
    }
}

/// The STM32F4 FSMC bridge: MCU bus to the register and RAM ports.
pub fn fsmc_bridge() -> VerilogModule {
    module(
        FsmcBridge::new(),
        "fsmc_bridge",
        "STM32F4 FSMC (NE1, mode 1, 16-bit) to a 32-bit register port (tear-free halves) \
         and a 16-bit RAM port; synchronised strobes (docs/fsmc_bridge.md)",
    )
}

/// The top level for `config`: FSMC and ISA bridges, identity block and
/// counter bank (docs/motion_controller.md), with the shared RAM inside the
/// FPGA or the port of an external dual-port SRAM (the ports differ).
pub fn motion_controller(config: &Config) -> VerilogModule {
    const SUMMARY: &str = "motion-controller top level: FSMC (MCU) and ISA (PC) bridges, \
                           identity block, counter bank, shared RAM (docs/motion_controller.md)";
    macro_rules! top {
        ($top:ident, $($n:literal)+) => {
            match config.axes() {
                $($n => module($top::<$n>::new(config), "motion_controller", SUMMARY),)+
                n => panic!("axes = {n} out of range 1..=16"),
            }
        };
    }
    match config.isa_ram() {
        IsaRam::Internal if config.servo_dac() => {
            top!(MotionControllerServo, 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
        }
        IsaRam::Internal => top!(MotionController, 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16),
        IsaRam::External => {
            top!(MotionControllerExternal, 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
        }
    }
}

/// The step/pulse generator of one axis (NCO, step queue, output timing).
pub fn pulse_generator() -> VerilogModule {
    module(
        PulseGenerator::new(),
        "pulse_generator",
        "step/pulse generator of one axis: 32-bit NCO, signed step queue, step length/space and \
         direction set-up/hold timing; S1/S2 for the pulse-mode selector (docs/pulse_generator.md)",
    )
}

/// The safety and I/O block of `axes` axes (1..=16) with its machine
/// inputs' filter ticking every `tick_clocks` clocks: e-stop latch,
/// watchdog, drive enables, limits, home, alarm, interrupt causes and masks.
pub fn safety_io(axes: u32, tick_clocks: u32) -> VerilogModule {
    const SUMMARY: &str = "safety and I/O block: fail-safe e-stop latch, key-fed watchdog, drive \
                           enables, filtered limit/home/alarm inputs with per-direction stops, \
                           interrupt causes, masks and IRQ pin (docs/safety_io.md)";
    macro_rules! block {
        ($($n:literal)+) => {
            match axes {
                $($n => module(SafetyIo::<$n>::new(tick_clocks), "safety_io", SUMMARY),)+
                _ => panic!("axes = {axes} out of range 1..=16"),
            }
        };
    }
    block!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// The servo DAC block for a clock of `clock_hz`: the DAC7744-style
/// interface and the servo tick.
pub fn servo_dac(clock_hz: u64) -> VerilogModule {
    module(
        crate::servo_dac::ServoDac::new(clock_hz),
        "servo_dac",
        "servo DAC block: four staged codes to a DAC7744-style parallel DAC, all \
         outputs updated by one LOADDACS rise a fixed time after the servo tick; \
         safe code on reset and e-stop (docs/servo_dac.md)",
    )
}

/// Every exported module for `config`.
pub fn all(config: &Config) -> Vec<VerilogModule> {
    vec![
        ls153(),
        ls688(),
        pulse_mode_selector(),
        pulse_mode_selector_registered(),
        counter_bank_with(
            config.axes(),
            config.counter_width(),
            config.counter_features(),
        ),
        quadrature_core(config.counter_width()),
        isa_bridge(config.isa_ram()),
        fsmc_bridge(),
        motion_controller(config),
        pulse_generator(),
        safety_io(config.axes(), config.filter_tick_clocks()),
        servo_dac(config.clock_hz()),
    ]
}
