//! Simulation throughput, for `motionhdl bench`: the default 4×28 counter
//! bank, and the default top (`motion_controller` from `Config::default()`:
//! 4 axes, 28-bit counters, RAM inside). Measurements, not tests: nothing
//! here asserts a speed.

use crate::checks::counter_bank::stimulus::{model_sums, verilog_sums_timed, Stimulus};
use crate::checks::motion_controller::top_model;
use crate::checks::motion_controller::top_stimulus::{self, TopStimulus};
use crate::harness::{cycle, settle};
use crate::verilog_sim::Simulator;
use motionhdl_hdl::{CounterBank, MotionController};
use motionhdl_model::motion_controller::MotionControllerModel;
use motionhdl_model::{Config, CounterFeatures};
use rust_hdl::prelude::*;
use std::time::Instant;

/// One throughput measurement.
pub struct Throughput {
    pub engine: String,
    pub cycles: u64,
    pub seconds: f64,
    /// Whether the engine's output-pin checksum equals the model's over
    /// the same stimulus (`None`: not checked, or the model itself).
    pub agrees: Option<bool>,
}

impl Throughput {
    pub fn per_second(&self) -> f64 {
        self.cycles as f64 / self.seconds
    }
}

/// The model stepping the bank (stimulus generation included).
pub fn model(cycles: u64) -> Throughput {
    let t = Instant::now();
    std::hint::black_box(model_sums(4, 28, CounterFeatures::ALL, 1, cycles));
    Throughput {
        engine: "model (plain Rust)".into(),
        cycles,
        seconds: t.elapsed().as_secs_f64(),
        agrees: None,
    }
}

/// The rust-hdl bank stepped directly (`update_all` until settled, per
/// clock edge), no model beside it.
pub fn rust_hdl(cycles: u64) -> Throughput {
    let mut s = Stimulus::new(4, 28, 1);
    let mut bank = CounterBank::<4>::new(28);
    bank.connect_all();
    let t = Instant::now();
    for _ in 0..cycles {
        let c = s.clock();
        let word = |f: fn(&(bool, bool, bool)) -> bool| -> Bits<4> {
            c.pins
                .iter()
                .enumerate()
                .fold(0u64, |w, (i, p)| w | (u64::from(f(p)) << i))
                .into()
        };
        bank.a.next = word(|p| p.0);
        bank.b.next = word(|p| p.1);
        bank.z.next = word(|p| p.2);
        bank.home.next = u64::from(c.home).into();
        bank.reset.next = c.reset;
        bank.addr.next = (c.bus.addr as u64).into();
        bank.wdata.next = (c.bus.wdata as u64).into();
        bank.we.next = c.bus.we;
        bank.re.next = c.bus.re;
        settle(&mut bank);
        cycle(&mut bank, |b| &mut b.clock);
    }
    Throughput {
        engine: "rust-hdl block, stepped directly".into(),
        cycles,
        seconds: t.elapsed().as_secs_f64(),
        agrees: None,
    }
}

/// The generated Verilog in `sim` with the Verilog stimulus testbench
/// (simulation time only; compilation excluded).
pub fn verilog(sim: Simulator, cycles: u64) -> Result<Throughput, String> {
    let m = motionhdl_hdl::catalog::counter_bank(4, 28);
    let (_, elapsed) = verilog_sums_timed(sim, &m, &m.text, 28, 1, cycles)?;
    Ok(Throughput {
        engine: format!("{} (generated Verilog + testbench)", sim.name()),
        cycles,
        seconds: elapsed.as_secs_f64(),
        agrees: None,
    })
}

/// Seed of the top's stimulus in every engine.
pub const TOP_SEED: u32 = 1;

/// The configuration the top's table measures.
pub fn top_config() -> Config {
    Config::default()
}

/// The model stepping the default top (stimulus generation included).
pub fn top_model(cycles: u64) -> Throughput {
    let config = top_config();
    let mut s = TopStimulus::new(&config, TOP_SEED);
    let mut m = MotionControllerModel::new(&config);
    let mut sums = top_stimulus::Sums::default();
    let t = Instant::now();
    for _ in 0..cycles {
        let p = s.clock();
        let o = m.step(&p);
        sums.add(&p, &o);
    }
    let seconds = t.elapsed().as_secs_f64();
    std::hint::black_box(sums);
    Throughput {
        engine: "model (plain Rust)".into(),
        cycles,
        seconds,
        agrees: None,
    }
}

/// The rust-hdl `MotionController<4>` stepped directly (update loop until
/// settled: inputs, rising edge, falling edge), no model beside it; its
/// output checksum is then compared with the model's.
pub fn top_rust_hdl(cycles: u64) -> Throughput {
    let config = top_config();
    assert_eq!(config.axes(), 4, "the default top is MotionController<4>");
    let mut s = TopStimulus::new(&config, TOP_SEED);
    let mut uut = MotionController::<4>::new(&config);
    uut.connect_all();
    let mut sums = top_stimulus::Sums::default();
    let t = Instant::now();
    for _ in 0..cycles {
        let p = s.clock();
        let o = top_model::step_rust(&mut uut, &p);
        sums.add(&p, &o);
    }
    let seconds = t.elapsed().as_secs_f64();
    Throughput {
        engine: "rust-hdl MotionController<4>, stepped directly".into(),
        cycles,
        seconds,
        agrees: Some(sums == top_model::model_sums(&config, TOP_SEED, cycles)),
    }
}

/// The generated `motion_controller.v` in `sim` under the Verilog copy of
/// the stimulus generator (simulation time only; compilation excluded).
pub fn top_verilog(sim: Simulator, cycles: u64) -> Result<Throughput, String> {
    let config = top_config();
    let (sums, elapsed) = top_model::verilog_sums_timed(sim, &config, TOP_SEED, cycles)?;
    Ok(Throughput {
        engine: format!("{} (generated Verilog + testbench)", sim.name()),
        cycles,
        seconds: elapsed.as_secs_f64(),
        agrees: Some(sums == top_model::model_sums(&config, TOP_SEED, cycles)),
    })
}
