//! Safety and I/O block checks: the block against its model every clock
//! under random register traffic, e-stop episodes and move events (in
//! rust-hdl and as generated Verilog), and its contract, stated apart
//! from the model (docs/safety_io.md).

pub mod contract;

use crate::harness::{cycle, settle, CheckReport, Rng};
use crate::verilog_sim::{ports_of, run_vectors, sim_failure, Design, Target};
use motionhdl_hdl::probe::SafetyRegisters;
use motionhdl_hdl::{catalog, SafetyIo};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap;
use motionhdl_model::safety_io::{SafetyInputs, SafetyIo as Model, WATCHDOG_KEY};
use rust_hdl::prelude::*;

/// Axes of the instance the checks run.
pub const AXES: usize = 4;

/// One clock of the block's inputs.
#[derive(Clone, Copy, Debug, Default)]
pub struct Vector {
    pub reset: bool,
    pub bus: BusCycle,
    pub inputs: SafetyInputs,
}

/// The block's outputs after one edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outputs {
    pub rdata: u32,
    pub halt: bool,
    pub drive_enable: u32,
    pub irq: bool,
}

fn write_data(register: &str, next: &mut impl FnMut() -> u64) -> u32 {
    match register {
        "CLEAR" => (next() % 4) as u32,
        // Mostly short, so the watchdog bites within a run; sometimes off.
        "WDT_TIMEOUT" => match next() % 8 {
            0 => 0,
            1 => next() as u32,
            _ => (next() % 48) as u32,
        },
        "WDT_RELOAD" if !next().is_multiple_of(4) => WATCHDOG_KEY,
        _ => next() as u32,
    }
}

/// Random traffic: writes of every register (the watchdog key mostly
/// right), reads of every address, e-stop episodes from one clock long,
/// move-done and FIFO-low levels toggling, and rare resets.
pub fn stimulus(clocks: usize, seed: u64) -> Vec<Vector> {
    let map = regmap::safety_io(AXES as u32);
    let decoded = map.decoded();
    let mut next = Rng::stream(seed);
    let mut v = vec![
        Vector {
            reset: true,
            ..Default::default()
        };
        4
    ];
    let mut inputs = SafetyInputs {
        estop_ok: true,
        done: 0,
        low: 0,
    };
    let mut estop_low_for = 0;
    while v.len() < clocks {
        if estop_low_for == 0 && next().is_multiple_of(300) {
            estop_low_for = 1 + next() % 20;
        }
        inputs.estop_ok = estop_low_for == 0;
        estop_low_for = estop_low_for.saturating_sub(1);
        if next().is_multiple_of(8) {
            inputs.done ^= 1 << (next() % AXES as u64);
        }
        if next().is_multiple_of(8) {
            inputs.low ^= 1 << (next() % AXES as u64);
        }
        let bus = match next() % 6 {
            0 => {
                let (addr, r, _) = decoded[(next() % decoded.len() as u64) as usize];
                BusCycle::write(addr, write_data(r.name, &mut next))
            }
            1 if next().is_multiple_of(8) => BusCycle::read((next() % 128) as u32),
            1 => BusCycle::read(decoded[(next() % decoded.len() as u64) as usize].0),
            _ => BusCycle::default(),
        };
        v.push(Vector {
            reset: next().is_multiple_of(3000),
            bus,
            inputs,
        });
    }
    v.truncate(clocks);
    v
}

/// What the model says the outputs are after each vector's edge.
pub fn model_outputs(vectors: &[Vector]) -> Vec<Outputs> {
    let mut model = Model::new(AXES as u32);
    vectors
        .iter()
        .map(|v| {
            model.clock(v.reset, &v.bus, &v.inputs);
            Outputs {
                rdata: model.rdata(),
                halt: model.halted(),
                drive_enable: model.drive_enable(),
                irq: model.irq_pin(),
            }
        })
        .collect()
}

/// One clock as the contract sees it: the inputs, then the outputs and
/// the interrupt registers after the edge.
#[derive(Clone, Copy, Debug)]
pub struct Observed {
    pub vector: Vector,
    pub outputs: Outputs,
    pub registers: SafetyRegisters,
}

/// The rust-hdl block, stepped directly: one [`Observed`] per vector.
pub fn run_rust(vectors: &[Vector]) -> Vec<Observed> {
    let mut uut = SafetyIo::<AXES>::new();
    uut.connect_all();
    vectors
        .iter()
        .map(|v| {
            uut.reset.next = v.reset;
            uut.addr.next = u64::from(v.bus.addr & 0x7f).into();
            uut.wdata.next = u64::from(v.bus.wdata).into();
            uut.we.next = v.bus.we;
            uut.re.next = v.bus.re;
            uut.estop_ok.next = v.inputs.estop_ok;
            uut.done.next = u64::from(v.inputs.done).into();
            uut.low.next = u64::from(v.inputs.low).into();
            settle(&mut uut);
            cycle(&mut uut, |u| &mut u.clock);
            Observed {
                vector: *v,
                outputs: Outputs {
                    rdata: uut.rdata.val().index() as u32,
                    halt: uut.halt.val(),
                    drive_enable: uut.drive_enable.val().index() as u32,
                    irq: uut.irq.val(),
                },
                registers: uut.probe(),
            }
        })
        .collect()
}

/// The rust-hdl block against the model every clock. One case per clock.
pub fn random_rust(clocks: usize, seed: u64) -> CheckReport {
    let mut r = CheckReport::new(
        "safety_io",
        &format!("{AXES} axes, {clocks} random clocks: rust-hdl vs model"),
        clocks as u64,
    );
    let vectors = stimulus(clocks, seed);
    let want = model_outputs(&vectors);
    for (k, (o, w)) in run_rust(&vectors).iter().zip(&want).enumerate() {
        r.case((o.outputs != *w).then(|| {
            format!(
                "clock {k} {:?}: HDL {:?}, model {w:?}",
                vectors[k], o.outputs
            )
        }));
    }
    r
}

/// The generated Verilog (or its netlist) against the model every clock.
pub fn random_verilog(target: impl Into<Target>, clocks: usize, seed: u64) -> CheckReport {
    let target = target.into();
    let mut r = CheckReport::new(
        "safety_io",
        &format!(
            "{AXES} axes, {clocks} random clocks: {} vs model",
            target.describe()
        ),
        clocks as u64,
    );
    let vectors = stimulus(clocks, seed);
    let want = model_outputs(&vectors);
    let module = catalog::safety_io(AXES as u32);
    let text = match target.text(&module) {
        Ok(text) => text,
        Err(e) => return sim_failure(r, target, e),
    };
    let design = Design {
        top: module.name,
        source: &text,
        inputs: ports_of(
            &module,
            &[
                "reset", "addr", "wdata", "we", "re", "estop_ok", "done", "low",
            ],
        ),
        outputs: ports_of(&module, &["rdata", "halt", "drive_enable", "irq"]),
        clock: Some("clock"),
    };
    let mut rows: Vec<Vec<u64>> = vectors
        .iter()
        .map(|v| {
            vec![
                u64::from(v.reset),
                u64::from(v.bus.addr & 0x7f),
                u64::from(v.bus.wdata),
                u64::from(v.bus.we),
                u64::from(v.bus.re),
                u64::from(v.inputs.estop_ok),
                u64::from(v.inputs.done),
                u64::from(v.inputs.low),
            ]
        })
        .collect();
    rows.push(vec![0; 8]);
    match run_vectors(target.sim, &design, &rows) {
        Ok(out) => {
            for (k, w) in want.iter().enumerate() {
                let got = &out[k + 1];
                let expect = [
                    u64::from(w.rdata),
                    u64::from(w.halt),
                    u64::from(w.drive_enable),
                    u64::from(w.irq),
                ];
                r.case((got[..] != expect[..]).then(|| {
                    format!(
                        "clock {k} {:?}: Verilog {got:?}, model {expect:?}",
                        vectors[k]
                    )
                }));
            }
        }
        Err(e) => return sim_failure(r, target, e),
    }
    r
}

/// The block's checks `motionhdl verify` runs: the model comparison, the
/// contract (each property a row), and with `external` the generated
/// Verilog in Icarus and Verilator.
pub fn all(external: bool) -> Vec<CheckReport> {
    use crate::verilog_sim::Simulator;
    let mut v = vec![random_rust(100_000, 0x5afe_0001)];
    v.extend(contract::contract(&run_rust(&stimulus(
        100_000,
        0x5afe_0006,
    ))));
    if external {
        v.push(random_verilog(Simulator::Icarus, 100_000, 0x5afe_0002));
        v.push(random_verilog(Simulator::Verilator, 1_000_000, 0x5afe_0003));
    }
    v
}
