//! The top level through the MCU's pins: every register of the map and the
//! shared RAM window read and written by the STM32F4 FSMC bus-functional
//! model (`fsmc_bridge`'s, with the documented timing), in rust-hdl and in
//! the generated `motion_controller.v`, against an oracle built from the
//! register-map table, the counter bank model and a RAM array.

use crate::bfm::fsmc::{
    self, documented_timing, timeline, Event, Observation, Op, CLOCK_TICKS, FIRST_EDGE_TICKS,
};
use crate::harness::{cycle, settle, CheckReport};
use crate::player::{PinStream, Rig};
use crate::verilog_sim::{Simulator, Source, Target};
use motionhdl_hdl::{catalog, MotionController, MotionControllerExternal, MotionControllerServo};
use motionhdl_model::fsmc_bridge::FsmcPins;
use motionhdl_model::{Config, IsaRam};
use rust_hdl::prelude::*;

pub mod driver_bus;
pub mod estop;
mod external_window;
pub mod homing;
pub mod irq_refill;
pub mod limit_stop;
mod loopback;
mod motion_plot;
mod oracle;
pub mod servo_tick;
pub mod system;
mod top_engine;
pub mod top_model;
pub mod top_stimulus;
pub mod watchdog_bite;

pub use external_window::*;
pub use loopback::*;
pub use oracle::*;

/// The pins both top-level builds share with the bench.
pub trait McuTop: Block {
    /// Drives the FSMC pins and reset; the PC side idles (no strobes, AEN
    /// high: a DMA cycle, never ours) and the encoders stay low.
    fn drive(&mut self, p: &FsmcPins, reset: bool);
    /// `fsmc_d_oe` and `fsmc_d_out`.
    fn data(&self) -> (bool, u16);
    fn clock_input(&mut self) -> &mut Signal<In, Clock>;
    /// The loopback wiring: encoder A/B inputs = pulse outputs F1/F2.
    fn feed_back(&mut self);
}

macro_rules! mcu_top {
    ($top:ident) => {
        impl<const N: usize> McuTop for $top<N> {
            fn drive(&mut self, p: &FsmcPins, reset: bool) {
                self.reset.next = reset;
                self.fsmc_ne_n.next = p.ne_n;
                self.fsmc_noe_n.next = p.noe_n;
                self.fsmc_nwe_n.next = p.nwe_n;
                self.fsmc_a.next = u64::from(p.a).into();
                self.fsmc_d_in.next = u64::from(p.d_in).into();
                self.isa_ior_n.next = true;
                self.isa_iow_n.next = true;
                self.isa_aen.next = true;
                self.estop_ok.next = true;
            }
            fn data(&self) -> (bool, u16) {
                (self.fsmc_d_oe.val(), self.fsmc_d_out.val().index() as u16)
            }
            fn clock_input(&mut self) -> &mut Signal<In, Clock> {
                &mut self.clock
            }
            fn feed_back(&mut self) {
                self.enc_a.next = self.pulse_f1.val();
                self.enc_b.next = self.pulse_f2.val();
            }
        }
    };
}
mcu_top!(MotionController);
mcu_top!(MotionControllerExternal);
mcu_top!(MotionControllerServo);

/// Steps the rust-hdl top for `config` (either build) through `ops`.
pub fn run_rust<const N: usize>(config: &Config, ops: &[Op]) -> (Vec<Observation>, u64) {
    match config.isa_ram() {
        IsaRam::Internal if config.servo_dac() => {
            run_top(MotionControllerServo::<N>::new(config), ops, bare_board)
        }
        IsaRam::Internal => run_top(MotionController::<N>::new(config), ops, bare_board),
        IsaRam::External => run_top(MotionControllerExternal::<N>::new(config), ops, bare_board),
    }
}

/// What the board around a rust-hdl top does at each clock: called with
/// the pins driven and settled just before the rising edge
/// ([`Edge::Before`]) and once the clock has fallen again ([`Edge::After`]).
/// A board that drives an input before the edge settles the top itself;
/// after the edge it need not, since every sample and every edge starts by
/// driving the pins and settling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    Before,
    After,
}

/// The encoder inputs following the pulse outputs.
pub fn loopback_board<T: McuTop>(uut: &mut T, edge: Edge) {
    if edge == Edge::Before {
        uut.feed_back();
        settle(uut);
    }
}

/// Nothing on the board beyond the ties of [`McuTop::drive`].
pub fn bare_board<T: McuTop>(_: &mut T, _: Edge) {}

/// Steps a rust-hdl top through `ops` under the FSMC BFM, with `board`
/// around it: what each read observed at the MCU's pins, and the clocks
/// simulated.
pub fn run_top<T: McuTop>(
    mut uut: T,
    ops: &[Op],
    mut board: impl FnMut(&mut T, Edge),
) -> (Vec<Observation>, u64) {
    let (events, end) = timeline(ops, &documented_timing());
    uut.connect_all();
    let mut pins = FsmcPins::idle();
    let mut reset = false;
    let mut observations = Vec::new();
    let mut pending = None;
    let mut clocks = 0;
    let mut edge = FIRST_EDGE_TICKS;
    let mut i = 0;
    while edge <= end || i < events.len() {
        while i < events.len() && events[i].0 < edge {
            match events[i].1 {
                Event::Pins(p, r) => {
                    pins = p;
                    reset = r;
                }
                Event::ObserveSetup | Event::ObserveEnd => {
                    uut.drive(&pins, reset);
                    settle(&mut uut);
                    let now = uut.data();
                    if matches!(events[i].1, Event::ObserveSetup) {
                        pending = Some(now);
                    } else {
                        let (oe_setup, data_setup) = pending.take().expect("setup first");
                        observations.push(Observation {
                            oe_setup,
                            oe_end: now.0,
                            data_setup,
                            data_end: now.1,
                        });
                    }
                }
            }
            i += 1;
        }
        if edge > end {
            break;
        }
        uut.drive(&pins, reset);
        settle(&mut uut);
        board(&mut uut, Edge::Before);
        cycle(&mut uut, |u| u.clock_input());
        board(&mut uut, Edge::After);
        clocks += 1;
        edge += CLOCK_TICKS;
    }
    (observations, clocks)
}

/// The top in `target` with an idle PC side (no strobes, AEN high: a DMA
/// cycle, never ours), the encoder inputs low or, with `loopback`, every
/// axis's pulse outputs wired back to its encoder inputs (A = F1, B = F2),
/// and the external RAM build's SRAM and window data buses reading 0.
fn rig(target: Target, config: &Config, loopback: bool) -> Result<Rig, String> {
    let module = catalog::motion_controller(config);
    let mut rig = Rig::new(&module, target.text(&module)?, fsmc::CLOCK);
    let idle_pc: [(&str, u64); 7] = [
        ("isa_sa", 0),
        ("isa_sd_in", 0),
        ("isa_ior_n", 1),
        ("isa_iow_n", 1),
        ("isa_aen", 1),
        ("isa_bale", 0),
        ("isa_base", 0),
    ];
    let mut ties: Vec<(&str, u64)> = idle_pc.to_vec();
    ties.extend([
        ("enc_z", 0),
        ("estop_ok", 1),
        ("limit_pos", 0),
        ("limit_neg", 0),
        ("home", 0),
        ("alarm", 0),
        ("gpi", 0),
    ]);
    if loopback {
        rig.loops = vec![
            ("enc_a".into(), "pulse_f1".into()),
            ("enc_b".into(), "pulse_f2".into()),
        ];
    } else {
        ties.extend([("enc_a", 0), ("enc_b", 0)]);
    }
    if config.isa_ram() == IsaRam::External {
        ties.extend([("sram_d_in", 0), ("window_rdata", 0)]);
    }
    rig.ties = ties.into_iter().map(|(n, v)| (n.to_string(), v)).collect();
    rig.sampled = vec!["fsmc_d_oe".into(), "fsmc_d_out".into()];
    Ok(rig)
}

/// The FSMC bus-functional model's stream for `ops` on the top's
/// `fsmc_`-prefixed pins.
fn top_stream(ops: &[Op]) -> PinStream {
    fsmc::stream(ops, &documented_timing()).renamed(|n| match n {
        "reset" => n.to_string(),
        _ => format!("fsmc_{n}"),
    })
}

/// Runs `ops` through the generated `motion_controller.v` in `target`.
pub fn run_verilog(
    target: impl Into<Target>,
    config: &Config,
    ops: &[Op],
) -> Result<Vec<Observation>, String> {
    play(target.into(), config, ops, false)
}

pub(super) fn play(
    t: Target,
    config: &Config,
    ops: &[Op],
    loopback: bool,
) -> Result<Vec<Observation>, String> {
    t.available()?;
    let samples = rig(t, config, loopback)?.play(t.sim, &top_stream(ops))?;
    fsmc::observations(&samples)
}

/// One case per read halfword: driven from the setup point to the end, with
/// the value the oracle expects.
pub fn compare(name: &str, plan: &Plan, got: &[Observation]) -> CheckReport {
    let mut r = CheckReport::new("motion_controller", name, plan.expected.len() as u64);
    if got.len() != plan.expected.len() {
        r.failures.push(format!(
            "{} reads observed, {} expected",
            got.len(),
            plan.expected.len()
        ));
        return r;
    }
    // Name each read for the failure message.
    let mut names = Vec::new();
    for op in &plan.ops {
        match *op {
            Op::Read16 { a } => names.push(format!("Read16 A={a:#05x}")),
            Op::Read32 { a } => {
                names.push(format!("Read32 A={a:#05x} low"));
                names.push(format!("Read32 A={a:#05x} high"));
            }
            _ => {}
        }
    }
    for (k, (g, want)) in got.iter().zip(&plan.expected).enumerate() {
        let ok = g.oe_setup && g.oe_end && g.data_setup == *want && g.data_end == *want;
        r.case((!ok).then(|| {
            format!(
                "read #{k} ({}): observed {g:?}, expected {want:#06x}",
                names[k]
            )
        }));
    }
    r
}

/// Every register and RAM word of `config`'s top through the Verilog FSMC
/// BFM in `target` (the generated file or its netlist), against the plan.
pub fn check_verilog(target: impl Into<Target>, config: &Config) -> CheckReport {
    let t = target.into();
    let plan = plan(config);
    let label = match t.source {
        Source::Generated => t.sim.name().to_string(),
        _ => t.describe(),
    };
    let name = format!(
        "every register word through FSMC, {} RAM, {label}",
        config.isa_ram().name()
    );
    match run_verilog(t, config, &plan.ops) {
        Ok(obs) => compare(&name, &plan, &obs),
        Err(e) => {
            let r = CheckReport::new("motion_controller", &name, plan.expected.len() as u64);
            if t.available().is_err() {
                r.skip(e)
            } else {
                let mut r = r;
                r.failures.push(e);
                r
            }
        }
    }
}

/// The checks `motionhdl verify` shows for the top (default 4 axes): every
/// register and RAM word through the FSMC pins, both RAM builds, in
/// rust-hdl and with `external` in Icarus and Verilator.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = Vec::new();
    for ram in [IsaRam::Internal, IsaRam::External] {
        let config = Config::default().with_isa_ram(ram);
        let plan = plan(&config);
        v.push(compare(
            &format!(
                "every register word through FSMC, {} RAM, rust-hdl",
                ram.name()
            ),
            &plan,
            &run_rust::<4>(&config, &plan.ops).0,
        ));
        if external {
            for sim in [Simulator::Icarus, Simulator::Verilator] {
                v.push(check_verilog(sim, &config));
            }
        }
    }
    v
}
