//! The whole top (`motion_controller`, RAM inside) against its model,
//! pin for pin, every clock: the rust-hdl top beside the model under the
//! deterministic pin stimulus of [`crate::checks::motion_controller::top_stimulus`] (or the FSMC pins
//! of the STM32F4 bus-functional model), and the generated Verilog under
//! the stimulus's Verilog twin, whose checksums must equal the model's.

use crate::bfm::fsmc::{timeline, Event, Op, CLOCK_TICKS, FIRST_EDGE_TICKS};
use crate::checks::motion_controller::servo_tick::{self, TickSample, TickWatch};
use crate::checks::motion_controller::top_stimulus::{
    verilog_testbench, Sums, TopStimulus, RESET_CLOCKS,
};
use crate::harness::{cycle, settle, CheckReport};
use crate::verilog_sim::{run_for_sums, Target};
use motionhdl_hdl::{McuSide, MotionController, MotionControllerServo};
use motionhdl_model::fsmc_bridge::FsmcPins;
use motionhdl_model::motion_controller::{MotionControllerModel, TopInputs, TopOutputs};
use motionhdl_model::Config;
use rust_hdl::prelude::*;

/// The model's checksums after `cycles` clocks of stimulus from `seed`.
pub fn model_sums(config: &Config, seed: u32, cycles: u64) -> Sums {
    let mut s = TopStimulus::new(config, seed);
    let mut m = MotionControllerModel::new(config);
    let mut sums = Sums::default();
    for _ in 0..cycles {
        let p = s.clock();
        let o = m.step(&p);
        sums.add(&p, &o);
    }
    sums
}

/// A rust-hdl top the model twins pin for pin (the RAM-inside builds:
/// without and with SERVO).
pub trait ModelledTop<const N: usize>: Block {
    fn build(config: &Config) -> Self;
    /// Puts `p` on the input pins.
    fn drive(&mut self, p: &TopInputs);
    /// The output pins (the DAC's 0 on a top without one, as the model).
    fn outputs(&self) -> TopOutputs;
    fn mcu(&self) -> &McuSide<N>;
    fn clock_pin(&mut self) -> &mut Signal<In, Clock>;
}

macro_rules! modelled_top {
    ($top:ident, |$uut:ident, $o:ident| $dac:block) => {
        impl<const N: usize> ModelledTop<N> for $top<N> {
            fn build(config: &Config) -> Self {
                $top::<N>::new(config)
            }
            fn drive(&mut self, p: &TopInputs) {
                self.reset.next = p.reset;
                self.fsmc_ne_n.next = p.fsmc_ne_n;
                self.fsmc_noe_n.next = p.fsmc_noe_n;
                self.fsmc_nwe_n.next = p.fsmc_nwe_n;
                self.fsmc_a.next = u64::from(p.fsmc_a & 0xfff).into();
                self.fsmc_d_in.next = u64::from(p.fsmc_d_in).into();
                self.isa_sa.next = u64::from(p.isa_sa & 0x3ff).into();
                self.isa_sd_in.next = u64::from(p.isa_sd_in).into();
                self.isa_ior_n.next = p.isa_ior_n;
                self.isa_iow_n.next = p.isa_iow_n;
                self.isa_aen.next = p.isa_aen;
                self.isa_bale.next = p.isa_bale;
                self.isa_base.next = u64::from(p.isa_base).into();
                self.enc_a.next = u64::from(p.enc_a).into();
                self.enc_b.next = u64::from(p.enc_b).into();
                self.enc_z.next = u64::from(p.enc_z).into();
                self.estop_ok.next = p.estop_ok;
                self.limit_pos.next = u64::from(p.machine.limit_pos).into();
                self.limit_neg.next = u64::from(p.machine.limit_neg).into();
                self.home.next = u64::from(p.machine.home).into();
                self.alarm.next = u64::from(p.machine.alarm).into();
                self.gpi.next = u64::from(p.machine.gpi).into();
            }
            fn outputs(&self) -> TopOutputs {
                #[allow(unused_mut)]
                let mut $o = TopOutputs {
                    fsmc_d_out: self.fsmc_d_out.val().index() as u16,
                    fsmc_d_oe: self.fsmc_d_oe.val(),
                    isa_sd_out: self.isa_sd_out.val().index() as u16,
                    isa_sd_oe: self.isa_sd_oe.val(),
                    isa_iocs16_n: self.isa_iocs16_n.val(),
                    isa_irq: self.isa_irq.val(),
                    pulse_f1: self.pulse_f1.val().index() as u16,
                    pulse_f2: self.pulse_f2.val().index() as u16,
                    drive_enable: self.drive_enable.val().index() as u16,
                    irq: self.irq.val(),
                    gpo_out: self.gpo_out.val().index() as u16,
                    gpo_oe: self.gpo_oe.val().index() as u16,
                    ..Default::default()
                };
                let $uut = self;
                $dac
                $o
            }
            fn mcu(&self) -> &McuSide<N> {
                $top::mcu(self)
            }
            fn clock_pin(&mut self) -> &mut Signal<In, Clock> {
                &mut self.clock
            }
        }
    };
}

// No DAC on this top: the model's DAC pins read 0.
modelled_top!(MotionController, |_uut, o| {});
modelled_top!(MotionControllerServo, |uut, o| {
    o.dac_data = uut.dac_data.val().index() as u16;
    o.dac_addr = uut.dac_addr.val().index() as u8;
    o.dac_cs_n = uut.dac_cs_n.val();
    o.dac_rw_n = uut.dac_rw_n.val();
    o.dac_ldac_n = uut.dac_ldac_n.val();
    o.dac_sclk = uut.dac_sclk.val();
    o.dac_sdin = uut.dac_sdin.val();
    o.dac_sync_n = uut.dac_sync_n.val();
});

/// The rust-hdl top's output pins with `p` on its input pins, before the
/// edge.
pub fn sample<const N: usize>(uut: &mut impl ModelledTop<N>, p: &TopInputs) -> TopOutputs {
    uut.drive(p);
    settle(uut);
    uut.outputs()
}

/// The rising and falling clock edges of the rust-hdl top (the falling
/// one settles with the next [`sample`]: [`crate::harness::cycle`]).
pub fn clock_edge<const N: usize, T: ModelledTop<N>>(uut: &mut T) {
    cycle(uut, |u| u.clock_pin());
}

/// One clock of the rust-hdl top: [`sample`], then [`clock_edge`].
pub fn step_rust<const N: usize>(uut: &mut impl ModelledTop<N>, p: &TopInputs) -> TopOutputs {
    let o = sample(uut, p);
    clock_edge(uut);
    o
}

/// Per-clock FSMC pins and reset from the STM32F4 bus-functional model
/// (`fsmc_bridge::timeline`, documented timing): the pins as they are at
/// each rising edge.
pub fn bfm_clocks(ops: &[Op]) -> Vec<(FsmcPins, bool)> {
    let (events, end) = timeline(ops, &crate::bfm::fsmc::documented_timing());
    let mut out = Vec::new();
    let mut pins = FsmcPins::idle();
    let mut reset = false;
    let mut i = 0;
    let mut edge = FIRST_EDGE_TICKS;
    while edge <= end {
        while i < events.len() && events[i].0 < edge {
            if let Event::Pins(p, r) = events[i].1 {
                pins = p;
                reset = r;
            }
            i += 1;
        }
        out.push((pins, reset));
        edge += CLOCK_TICKS;
    }
    out
}

/// One axis's generator outputs as the stop contract sees them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AxisOutputs {
    /// S1, S2.
    pub step: bool,
    pub dir: bool,
    /// Steps emitted.
    pub position: u32,
}

/// The top's stop contract, from HALT and each axis's generator outputs
/// (S1, S2, position) alone: once HALT has been high at one edge, S1 does
/// not rise and S2 does not change at the later edges while it stays high,
/// and from the edge after that `position` does not change (a step whose
/// S1 rose at HALT's own edge still counts). The pins follow S1, S2 and
/// the position through registers (docs/pulse_generator.md, "HALT"). Fed
/// the samples after each edge, in order.
#[derive(Clone, Debug, Default)]
pub struct HaltWatch {
    /// Samples in a row with HALT high.
    run: u32,
    /// Axis-samples the property applied to.
    pub checked: u64,
    /// (sample, axis) where an output moved although it must not.
    pub violations: Vec<(u64, usize)>,
}

impl HaltWatch {
    /// Sample `k`: HALT and the axes' outputs, and those of the sample
    /// before.
    pub fn observe(
        &mut self,
        k: u64,
        (reset, halt): (bool, bool),
        now: &[AxisOutputs],
        before: &[AxisOutputs],
    ) {
        // A reset edge zeroes the positions: the runs start over.
        self.run = if halt && !reset { self.run + 1 } else { 0 };
        // HALT rose at edge h: sample h (run 1) may still show a step
        // started at h; sample h + 1 (run 2) shows none; its position may
        // still count the step of edge h.
        if self.run < 2 {
            return;
        }
        for (i, (n, b)) in now.iter().zip(before).enumerate() {
            self.checked += 1;
            let moved = (n.step && !b.step)
                || n.dir != b.dir
                || (self.run >= 3 && n.position != b.position);
            if moved {
                self.violations.push((k, i));
            }
        }
    }
}

/// The top's direction-stop contract, from the safety block's per-axis
/// stops and each axis's `position` alone: once `stop_up[i]` has been high
/// at three edges in a row, axis i's position does not rise at the later
/// edges while it stays high (a step whose S1 rose at the edge before the
/// stop acted still counts), and the same downwards for `stop_down[i]`
/// (docs/pulse_generator.md, "Direction stops"). A decelerating stop
/// steps on while its axis brakes (its bound is the bank's braking
/// contract), so the three edges count from the end of the brake.
#[derive(Clone, Debug, Default)]
pub struct StopWatch {
    /// Per axis, samples in a row with stop_up / stop_down high.
    runs: Vec<(u32, u32)>,
    /// Axis-samples the property applied to.
    pub checked: u64,
    /// Of those, samples where the axis's position changed (it backed off).
    pub moving: u64,
    /// Axis-samples under a stop that the axis spent braking.
    pub braking: u64,
    /// (sample, axis) where the position moved into a stop.
    pub violations: Vec<(u64, usize)>,
}

impl StopWatch {
    /// Sample `k`: the stops and the axes' outputs, and those before.
    pub fn observe(
        &mut self,
        k: u64,
        (reset, up, down, braking): (bool, u32, u32, u32),
        now: &[AxisOutputs],
        before: &[AxisOutputs],
    ) {
        self.runs.resize(now.len(), (0, 0));
        for (i, (n, b)) in now.iter().zip(before).enumerate() {
            let run = &mut self.runs[i];
            let brakes = braking >> i & 1 == 1;
            self.braking += u64::from(brakes && (up | down) >> i & 1 == 1);
            let held = |stop: u32| stop >> i & 1 == 1 && !reset && !brakes;
            run.0 = if held(up) { run.0 + 1 } else { 0 };
            run.1 = if held(down) { run.1 + 1 } else { 0 };
            let step = n.position.wrapping_sub(b.position) as i32;
            for (run, into) in [(run.0, step > 0), (run.1, step < 0)] {
                if run >= 3 {
                    self.checked += 1;
                    self.moving += u64::from(step != 0);
                    if into {
                        self.violations.push((k, i));
                    }
                }
            }
        }
    }
}

/// The generator outputs of every axis of the rust-hdl top.
pub fn axis_outputs<const N: usize>(uut: &impl ModelledTop<N>) -> Vec<AxisOutputs> {
    (0..N)
        .map(|i| {
            let g = uut.mcu().pulses().generator(i);
            AxisOutputs {
                step: g.step.val(),
                dir: g.dir.val(),
                position: g.position.val().index() as u32,
            }
        })
        .collect()
}

/// What one comparison run saw besides mismatches.
#[derive(Clone, Debug, Default)]
pub struct RunStats {
    /// Rising edges of F1 per axis (pulses came out).
    pub f1_edges: Vec<u64>,
    /// Clocks with FSMC D driven / ISA SD driven.
    pub fsmc_reads: u64,
    pub isa_reads: u64,
    /// Clocks in which some axis ran a segment (the model's move engines).
    pub move_clocks: u64,
    /// The stop contract over the HDL's pins.
    pub halt: HaltWatch,
    /// Clocks where HALT rose while some axis had a step queued or running
    /// (the contract's interesting case).
    pub halts_while_busy: u64,
    /// The direction-stop contract over the HDL's axes.
    pub stops: StopWatch,
    /// The servo card's top: the tick's contract, LOADDACS rises, and DAC
    /// writes (CS low) of a code other than the safe one.
    pub tick: Option<TickWatch>,
    pub ldac_rises: u64,
    pub unsafe_dac_writes: u64,
}

/// Where a comparison's per-clock pins come from.
pub enum Pins<'a> {
    /// [`TopStimulus`] from this seed.
    Generated(u32),
    /// The FSMC pins from the bus-functional model (see [`bfm_clocks`]),
    /// the ISA pins and reset from [`TopStimulus`] (seed), and the encoder
    /// A/B inputs looped back from the pulse outputs F1/F2 of the clock
    /// before (Z from the generator).
    Bfm(&'a [(FsmcPins, bool)], u32),
}

/// The safety block's (stop_up, stop_down, halt): the contracts above read
/// them, so they are only as good as these signals.
pub type SafetyStops = (u32, u32, bool);

/// The rust-hdl `MotionController<N>` and the model side by side for
/// `cycles` clocks: every output pin compared every clock (one case per
/// clock), and the safety block's (stop_up, stop_down, halt) with the
/// model's. `fault` may alter the model's outputs and that triple before
/// the comparison (to show that a wrong model is caught).
pub fn compare<const N: usize>(
    config: &Config,
    pins: Pins,
    cycles: u64,
    fault: impl FnMut(u64, &mut TopOutputs, &mut SafetyStops),
) -> (CheckReport, RunStats) {
    if config.servo_dac() {
        compare_on::<MotionControllerServo<N>, N>(config, pins, cycles, fault)
    } else {
        compare_on::<MotionController<N>, N>(config, pins, cycles, fault)
    }
}

/// [`compare`] on the top `T`.
fn compare_on<T: ModelledTop<N>, const N: usize>(
    config: &Config,
    pins: Pins,
    cycles: u64,
    mut fault: impl FnMut(u64, &mut TopOutputs, &mut SafetyStops),
) -> (CheckReport, RunStats) {
    let what = match pins {
        Pins::Generated(seed) => format!("generated pin stimulus, seed {seed}"),
        Pins::Bfm(..) => "STM32F4 FSMC bus-functional model, ISA traffic, pulse loopback".into(),
    };
    let mut r = CheckReport::new(
        "motion_controller",
        &format!("every output pin every clock, {cycles} clocks, {what}: rust-hdl vs model"),
        cycles,
    );
    let mut stats = RunStats {
        f1_edges: vec![0; N],
        tick: config.servo_dac().then(TickWatch::default),
        ..Default::default()
    };
    let (seed, bfm) = match pins {
        Pins::Generated(s) => (s, None),
        Pins::Bfm(v, s) => (s, Some(v)),
    };
    let mut stim = TopStimulus::new(config, seed);
    let mut model = MotionControllerModel::new(config);
    let mut uut = T::build(config);
    uut.connect_all();
    let mut last = TopOutputs::default();
    let mut last_halt = false;
    let mut last_axes = vec![AxisOutputs::default(); N];
    for k in 0..cycles {
        let mut p = stim.clock();
        if let Some(v) = bfm {
            let (f, reset) = v
                .get(k as usize)
                .copied()
                .unwrap_or((FsmcPins::idle(), false));
            p.fsmc_ne_n = f.ne_n;
            p.fsmc_noe_n = f.noe_n;
            p.fsmc_nwe_n = f.nwe_n;
            p.fsmc_a = f.a;
            p.fsmc_d_in = f.d_in;
            p.reset = reset || k < RESET_CLOCKS;
            p.enc_a = last.pulse_f1;
            p.enc_b = last.pulse_f2;
        }
        let busy = (0..N).any(|i| model.pulses().generator(i).busy());
        // step_rust, with the tick's watch on both sides of the edge.
        let got = sample(&mut uut, &p);
        if let Some(w) = &mut stats.tick {
            w.before_edge(k, &TickSample::of(&uut, &model, p.reset, got.dac_ldac_n));
        }
        clock_edge(&mut uut);
        if let Some(w) = &mut stats.tick {
            w.after_edge(k, &servo_tick::counts(&uut, |s| s.snap_count));
        }
        let halt = uut.mcu().halt();
        stats.halts_while_busy += u64::from(halt && !last_halt && busy);
        last_halt = halt;
        let axes = axis_outputs(&uut);
        stats.halt.observe(k, (p.reset, halt), &axes, &last_axes);
        let (up, down) = uut.mcu().stops();
        let braking = (0..N)
            .filter(|&i| uut.mcu().pulses().engine(i).braking.val())
            .fold(0u32, |m, i| m | 1 << i);
        stats
            .stops
            .observe(k, (p.reset, up, down, braking), &axes, &last_axes);
        last_axes = axes;
        let mut want = model.step(&p);
        let s = model.safety();
        let mut want_stops = (s.stop_up(), s.stop_down(), s.halted());
        fault(k, &mut want, &mut want_stops);
        let mut bad: Vec<String> = got
            .pins()
            .iter()
            .zip(want.pins())
            .filter(|(g, w)| g.1 != w.1)
            .map(|(g, w)| format!("{} HDL {:#x} model {:#x}", g.0, g.1, w.1))
            .collect();
        let got_stops = (up, down, halt);
        if got_stops != want_stops {
            bad.push(format!(
                "(stop_up, stop_down, halt) HDL {got_stops:x?} model {want_stops:x?}"
            ));
        }
        r.case((!bad.is_empty()).then(|| format!("clock {k}: {}; inputs {p:?}", bad.join(", "))));
        if r.failures.len() >= 5 {
            break;
        }
        for (i, e) in stats.f1_edges.iter_mut().enumerate() {
            *e += u64::from(got.pulse_f1 >> i & 1 == 1 && last.pulse_f1 >> i & 1 == 0);
        }
        stats.ldac_rises += u64::from(got.dac_ldac_n && !last.dac_ldac_n && config.servo_dac());
        stats.unsafe_dac_writes += u64::from(!got.dac_cs_n && got.dac_data != 0x8000);
        stats.fsmc_reads += u64::from(got.fsmc_d_oe);
        stats.isa_reads += u64::from(got.isa_sd_oe);
        stats.move_clocks += u64::from((0..N).any(|i| model.pulses().engine(i).active()));
        last = got;
    }
    (r, stats)
}

/// Runs `motion_controller.v` for `config` (the generated file, or its
/// post-synthesis netlist) under [`verilog_testbench`] in the target's
/// simulator: its checksums, and how long the simulation ran (compilation
/// and synthesis excluded).
pub fn verilog_sums_timed(
    target: impl Into<Target>,
    config: &Config,
    seed: u32,
    cycles: u64,
) -> Result<(Sums, std::time::Duration), String> {
    let target = target.into();
    target.available()?;
    let module = motionhdl_hdl::catalog::motion_controller(config);
    let text = target.text(&module)?;
    let (v, elapsed) = run_for_sums(
        target.sim,
        &[
            ("tb.v", verilog_testbench(&module, config, seed, cycles)),
            ("motion_controller.v", text),
        ],
        "top_bench_tb",
    )?;
    Ok((
        Sums {
            stimulus: v[0],
            outputs: v[1],
        },
        elapsed,
    ))
}
