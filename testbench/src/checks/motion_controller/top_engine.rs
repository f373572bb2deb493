//! The simulator under the whole-controller [`System`](super::system):
//! the rust-hdl `MotionController` stepped directly, or the generated
//! `motion_controller.v` Verilated and stepped through
//! [`crate::verilated`], behind the same pins. One scenario runs the same
//! on both (tests/system.rs compares their traces); the scenario tests use
//! [`Engine::for_scenarios`], `motionhdl trace`/`generate` rust-hdl.

use super::top_model::ModelledTop;
use crate::harness::{cycle, in_ci, settle, tool};
use crate::verilated::Verilated;
use motionhdl_hdl::{catalog, MotionController};
use motionhdl_model::motion_controller::{TopInputs, TopOutputs};
use motionhdl_model::{Config, IsaRam};
use rust_hdl::prelude::*;

/// Which simulator runs the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// The rust-hdl blocks, stepped in this process (about 460 µs a clock
    /// at 4 axes); what `motionhdl generate` traces with.
    RustHdl,
    /// The generated Verilog in Verilator (a few µs a clock).
    Verilator,
}

impl Engine {
    /// The engine for the scenario tests: Verilator; where it is missing,
    /// rust-hdl (the same checks, slower) with a note, and under CI a
    /// failure, as for every missing tool.
    pub fn for_scenarios() -> Self {
        match tool("verilator") {
            Ok(_) => Engine::Verilator,
            Err(why) => {
                assert!(!in_ci(), "CI installs every tool, but {why}");
                eprintln!("note: {why}; the scenario runs on rust-hdl instead (slower)");
                Engine::RustHdl
            }
        }
    }
}

/// Port numbers of the Verilated top, looked up once.
pub struct Ports {
    clock: u32,
    inputs: [u32; INPUTS.len()],
    outputs: [u32; OUTPUTS.len()],
}

/// The input ports, in the order [`input_values`] gives them.
const INPUTS: [&str; 22] = [
    "reset",
    "fsmc_ne_n",
    "fsmc_noe_n",
    "fsmc_nwe_n",
    "fsmc_a",
    "fsmc_d_in",
    "isa_sa",
    "isa_sd_in",
    "isa_ior_n",
    "isa_iow_n",
    "isa_aen",
    "isa_bale",
    "isa_base",
    "enc_a",
    "enc_b",
    "enc_z",
    "estop_ok",
    "limit_pos",
    "limit_neg",
    "home",
    "alarm",
    "gpi",
];

fn input_values(i: &TopInputs) -> [u64; INPUTS.len()] {
    let m = &i.machine;
    [
        u64::from(i.reset),
        u64::from(i.fsmc_ne_n),
        u64::from(i.fsmc_noe_n),
        u64::from(i.fsmc_nwe_n),
        u64::from(i.fsmc_a),
        u64::from(i.fsmc_d_in),
        u64::from(i.isa_sa),
        u64::from(i.isa_sd_in),
        u64::from(i.isa_ior_n),
        u64::from(i.isa_iow_n),
        u64::from(i.isa_aen),
        u64::from(i.isa_bale),
        u64::from(i.isa_base),
        u64::from(i.enc_a),
        u64::from(i.enc_b),
        u64::from(i.enc_z),
        u64::from(i.estop_ok),
        u64::from(m.limit_pos),
        u64::from(m.limit_neg),
        u64::from(m.home),
        u64::from(m.alarm),
        u64::from(m.gpi),
    ]
}

/// The output ports of the top without the servo DAC.
const OUTPUTS: [&str; 12] = [
    "fsmc_d_out",
    "fsmc_d_oe",
    "isa_sd_out",
    "isa_sd_oe",
    "isa_iocs16_n",
    "isa_irq",
    "pulse_f1",
    "pulse_f2",
    "drive_enable",
    "irq",
    "gpo_out",
    "gpo_oe",
];

fn output_values(o: [u64; OUTPUTS.len()]) -> TopOutputs {
    TopOutputs {
        fsmc_d_out: o[0] as u16,
        fsmc_d_oe: o[1] != 0,
        isa_sd_out: o[2] as u16,
        isa_sd_oe: o[3] != 0,
        isa_iocs16_n: o[4] != 0,
        isa_irq: o[5] != 0,
        pulse_f1: o[6] as u16,
        pulse_f2: o[7] as u16,
        drive_enable: o[8] as u16,
        irq: o[9] != 0,
        gpo_out: o[10] as u16,
        gpo_oe: o[11] as u16,
        ..TopOutputs::default()
    }
}

/// The top in one of the engines.
pub enum Top<const N: usize> {
    RustHdl(Box<MotionController<N>>),
    Verilator(Box<Verilated>, Ports),
}

impl<const N: usize> Top<N> {
    /// `config`'s top (the internal-RAM build without the servo DAC: the
    /// one `MotionController` is) in `engine`; panics when Verilator
    /// cannot build it.
    pub fn new(engine: Engine, config: &Config) -> Self {
        assert!(
            config.isa_ram() == IsaRam::Internal && !config.servo_dac(),
            "System runs the internal-RAM build without the servo DAC"
        );
        match engine {
            Engine::RustHdl => {
                let mut uut = MotionController::<N>::new(config);
                uut.connect_all();
                Top::RustHdl(Box::new(uut))
            }
            Engine::Verilator => {
                let module = catalog::motion_controller(config);
                let v = Verilated::new(&module).unwrap_or_else(|e| panic!("{e}"));
                let ports = Ports {
                    clock: v.port("clock"),
                    inputs: INPUTS.map(|p| v.port(p)),
                    outputs: OUTPUTS.map(|p| v.port(p)),
                };
                Top::Verilator(Box::new(v), ports)
            }
        }
    }

    /// Drives `i` and settles.
    pub fn drive(&mut self, i: &TopInputs) {
        match self {
            Top::RustHdl(u) => {
                u.drive(i);
                settle(u.as_mut());
            }
            Top::Verilator(v, p) => {
                for (port, value) in p.inputs.iter().zip(input_values(i)) {
                    v.set(*port, value);
                }
                v.eval();
            }
        }
    }

    /// One clock: the rising edge, settled, and the falling edge, which
    /// settles with the next [`Self::drive`] ([`crate::harness::cycle`]);
    /// the outputs then are the post-edge ones.
    pub fn cycle(&mut self) {
        match self {
            Top::RustHdl(u) => cycle(u.as_mut(), |u| &mut u.clock),
            Top::Verilator(v, p) => {
                v.set(p.clock, 1);
                v.eval();
                v.set(p.clock, 0);
            }
        }
    }

    /// The output pins now.
    pub fn outputs(&self) -> TopOutputs {
        match self {
            Top::RustHdl(u) => u.outputs(),
            Top::Verilator(v, p) => output_values(p.outputs.map(|port| v.get(port))),
        }
    }
}
