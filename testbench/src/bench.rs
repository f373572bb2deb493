//! Simulation throughput of the default 4×28 counter bank, for
//! `motionhdl bench`. Measurements, not tests: nothing here asserts a speed.

use crate::counter_stimulus::{model_sums, verilog_sums_timed, Stimulus};
use crate::harness::{cycle, settle};
use crate::verilog_sim::Simulator;
use motionhdl_hdl::CounterBank;
use rust_hdl::prelude::*;
use std::time::Instant;

/// One throughput measurement.
pub struct Throughput {
    pub engine: String,
    pub cycles: u64,
    pub seconds: f64,
}

impl Throughput {
    pub fn per_second(&self) -> f64 {
        self.cycles as f64 / self.seconds
    }
}

/// The model stepping the bank (stimulus generation included).
pub fn model(cycles: u64) -> Throughput {
    let t = Instant::now();
    std::hint::black_box(model_sums(4, 28, 1, cycles));
    Throughput {
        engine: "model (plain Rust)".into(),
        cycles,
        seconds: t.elapsed().as_secs_f64(),
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
    }
}

/// The generated Verilog in `sim` with the Verilog stimulus testbench
/// (simulation time only; compilation excluded).
pub fn verilog(sim: Simulator, cycles: u64) -> Result<Throughput, String> {
    let m = motionhdl_hdl::catalog::counter_bank(4, 28);
    let (_, elapsed) = verilog_sums_timed(sim, &m.text, 4, 28, 1, cycles)?;
    Ok(Throughput {
        engine: format!("{} (generated Verilog + testbench)", sim.name()),
        cycles,
        seconds: elapsed.as_secs_f64(),
    })
}
