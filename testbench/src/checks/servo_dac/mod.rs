//! Servo DAC block checks: the block against its model every clock under
//! random register traffic, ticks and safe episodes (in rust-hdl and as
//! generated Verilog), and its contract on the DAC pins, stated apart from
//! the model (docs/servo_dac.md).

pub mod contract;
pub mod serial;
pub mod tour;

use crate::harness::{cycle, random_bus_cycle, settle, CheckReport, Rng};
use crate::verilog_sim::{compare_clocked, ports_of, sim_failure, Design, Target};
use motionhdl_hdl::catalog;
use motionhdl_hdl::servo_dac::{ServoDac, SERVO_ADDRESS_BITS};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap;
use motionhdl_model::servo_dac::{
    serial_update_latency, update_latency, DacPins, ServoDac as Model, DAC_CHANNELS, SAFE_CODE,
};

const CH: usize = DAC_CHANNELS as usize;
use rust_hdl::prelude::*;

/// The clock of the instance the checks run: TIMING resets to 2 / 2.
pub const CLOCK_HZ: u64 = 50_000_000;

/// `addr` as the block decodes it: its word address bits.
pub fn word_address(addr: u32) -> u32 {
    addr & ((1 << SERVO_ADDRESS_BITS) - 1)
}

/// One clock of the block's inputs.
#[derive(Clone, Copy, Debug, Default)]
pub struct Vector {
    pub reset: bool,
    pub bus: BusCycle,
    pub safe: bool,
}

/// The block's outputs after one edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outputs {
    pub rdata: u32,
    pub tick: bool,
    pub pins: DacPins,
}

fn write_data(register: &str, next: &mut dyn FnMut() -> u64) -> u32 {
    match register {
        // Periods around a transfer's length, so ticks find it idle, busy
        // or ending; sometimes off.
        "TICK_PERIOD" => match next() % 8 {
            0 => 0,
            1 => 1 + (next() % 8) as u32,
            // Around a serial transfer's length.
            2 => 150 + (next() % 500) as u32,
            _ => 10 + (next() % 60) as u32,
        },
        // Mostly short times; sometimes the register's full range.
        "TIMING" if !next().is_multiple_of(8) => ((next() % 4) | ((next() % 4) << 8)) as u32,
        "SERIAL" if !next().is_multiple_of(64) => {
            ((next() % 2) | ((next() % 3) << 8) | ((next() % 4) << 16)) as u32
        }
        _ => next() as u32,
    }
}

/// Random traffic: writes of every register, reads of every address,
/// safe episodes from one clock long, and rare resets.
pub fn stimulus(clocks: usize, seed: u64) -> Vec<Vector> {
    let map = regmap::servo_dac(CLOCK_HZ);
    let mut next = Rng::stream(seed);
    let mut v = vec![
        Vector {
            reset: true,
            ..Default::default()
        };
        2
    ];
    let mut safe_for = 0;
    while v.len() < clocks {
        if safe_for == 0 && next().is_multiple_of(500) {
            safe_for = 1 + next() % 200;
        }
        let safe = safe_for > 0;
        safe_for = safe_for.saturating_sub(1);
        let bus = random_bus_cycle(&map, 8, &mut next, write_data);
        v.push(Vector {
            reset: next().is_multiple_of(5000),
            bus,
            safe,
        });
    }
    v.truncate(clocks);
    v
}

/// What the model says the outputs are after each vector's edge.
pub fn model_outputs(vectors: &[Vector]) -> Vec<Outputs> {
    let mut model = Model::new(CLOCK_HZ);
    vectors
        .iter()
        .map(|v| {
            model.clock(v.reset, &v.bus, v.safe);
            Outputs {
                rdata: model.rdata(),
                tick: model.tick(),
                pins: model.pins(),
            }
        })
        .collect()
}

/// One clock as the contract sees it: the inputs, then the outputs.
#[derive(Clone, Copy, Debug)]
pub struct Observed {
    pub vector: Vector,
    pub outputs: Outputs,
}

/// The rust-hdl block, stepped directly: one [`Observed`] per vector.
pub fn run_rust(vectors: &[Vector]) -> Vec<Observed> {
    let mut uut = ServoDac::new(CLOCK_HZ);
    uut.connect_all();
    vectors
        .iter()
        .map(|v| {
            uut.reset.next = v.reset;
            uut.addr.next = u64::from(word_address(v.bus.addr)).into();
            uut.wdata.next = u64::from(v.bus.wdata).into();
            uut.we.next = v.bus.we;
            uut.re.next = v.bus.re;
            uut.safe.next = v.safe;
            settle(&mut uut);
            cycle(&mut uut, |u| &mut u.clock);
            Observed {
                vector: *v,
                outputs: Outputs {
                    rdata: uut.rdata.val().index() as u32,
                    tick: uut.tick.val(),
                    pins: DacPins {
                        data: uut.dac_data.val().index() as u32,
                        addr: uut.dac_addr.val().index() as u32,
                        cs_n: uut.dac_cs_n.val(),
                        rw_n: uut.dac_rw_n.val(),
                        ldac_n: uut.dac_ldac_n.val(),
                        sclk: uut.dac_sclk.val(),
                        sdin: uut.dac_sdin.val(),
                        sync_n: uut.dac_sync_n.val(),
                    },
                },
            }
        })
        .collect()
}

/// The rust-hdl block against the model every clock. One case per clock.
pub fn random_rust(clocks: usize, seed: u64) -> CheckReport {
    let mut r = CheckReport::new(
        "servo_dac",
        &format!("{clocks} random clocks: rust-hdl vs model"),
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

fn flat(o: &Outputs) -> [u64; 10] {
    [
        u64::from(o.rdata),
        u64::from(o.tick),
        u64::from(o.pins.data),
        u64::from(o.pins.addr),
        u64::from(o.pins.cs_n),
        u64::from(o.pins.rw_n),
        u64::from(o.pins.ldac_n),
        u64::from(o.pins.sclk),
        u64::from(o.pins.sdin),
        u64::from(o.pins.sync_n),
    ]
}

/// The generated Verilog (or its netlist) against the model every clock.
pub fn random_verilog(target: impl Into<Target>, clocks: usize, seed: u64) -> CheckReport {
    let target = target.into();
    let r = CheckReport::new(
        "servo_dac",
        &format!("{clocks} random clocks: {} vs model", target.describe()),
        clocks as u64,
    );
    let vectors = stimulus(clocks, seed);
    let want = model_outputs(&vectors);
    let module = catalog::servo_dac(CLOCK_HZ);
    let text = match target.text(&module) {
        Ok(text) => text,
        Err(e) => return sim_failure(r, target, e),
    };
    let design = Design {
        top: module.name,
        source: &text,
        inputs: ports_of(&module, &["reset", "addr", "wdata", "we", "re", "safe"]),
        outputs: ports_of(
            &module,
            &[
                "rdata",
                "tick",
                "dac_data",
                "dac_addr",
                "dac_cs_n",
                "dac_rw_n",
                "dac_ldac_n",
                "dac_sclk",
                "dac_sdin",
                "dac_sync_n",
            ],
        ),
        clock: Some("clock"),
    };
    let rows: Vec<Vec<u64>> = vectors
        .iter()
        .map(|v| {
            vec![
                u64::from(v.reset),
                u64::from(word_address(v.bus.addr)),
                u64::from(v.bus.wdata),
                u64::from(v.bus.we),
                u64::from(v.bus.re),
                u64::from(v.safe),
            ]
        })
        .collect();
    let want: Vec<Vec<u64>> = want.iter().map(|w| flat(w).to_vec()).collect();
    compare_clocked(r, target, &design, rows, &want, |k| {
        format!("{:?}", vectors[k])
    })
}

/// The registers a transfer takes at its start, as the bus wrote them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Staged {
    pub codes: [u32; CH],
    /// SERIAL: MODE, SCLK_HALF, SYNC_HIGH.
    pub serial: (bool, u32, u32),
    pub prefix: u32,
    pub ldac_low: u32,
}

/// The staged registers after each vector's edge (reset: the map's).
pub fn staged(trace: &[Observed]) -> Vec<Staged> {
    let map = regmap::servo_dac(CLOCK_HZ);
    let ch = map.array("CH").clone();
    let serial = map.register("SERIAL");
    let reset = Staged {
        codes: [SAFE_CODE; CH],
        serial: (
            false,
            serial.field("SCLK_HALF").reset,
            serial.field("SYNC_HIGH").reset,
        ),
        prefix: map.register("PREFIX").reset,
        ldac_low: map.register("TIMING").field("LDAC_LOW").reset,
    };
    let at = |name: &str| map.register(name).offset;
    let mut s = reset;
    trace
        .iter()
        .map(|o| {
            let (bus, addr) = (o.vector.bus, word_address(o.vector.bus.addr));
            if o.vector.reset {
                s = reset;
            } else if bus.we {
                let w = bus.wdata;
                for (c, code) in s.codes.iter_mut().enumerate() {
                    if addr == ch.address(c as u32, "CODE") {
                        *code = w & 0xffff;
                    }
                }
                if addr == at("SERIAL") {
                    s.serial = (w & 1 == 1, w >> 8 & 0xff, w >> 16 & 0xff);
                } else if addr == at("PREFIX") {
                    s.prefix = w;
                } else if addr == at("TIMING") {
                    s.ldac_low = w >> 8 & 0xff;
                }
            }
            s
        })
        .collect()
}

/// Clocks from a transfer's start to its LOADDACS rise for the register
/// words TIMING = `timing` and SERIAL = `serial` of the block `map`:
/// `update_latency` on the parallel pins, `serial_update_latency` with
/// SERIAL.MODE = 1.
pub fn update_latency_of(map: &regmap::Block, timing: u32, serial: u32) -> u32 {
    let (t, s) = (map.register("TIMING"), map.register("SERIAL"));
    let ldac_low = t.field("LDAC_LOW").get(timing);
    match s.field("MODE").get(serial) {
        0 => update_latency(t.field("CS_LOW").get(timing), ldac_low),
        _ => serial_update_latency(
            s.field("SCLK_HALF").get(serial),
            s.field("SYNC_HIGH").get(serial),
            ldac_low,
        ),
    }
}

/// One report per contract property, none counted yet.
fn property_reports(properties: &[&str]) -> Vec<CheckReport> {
    properties
        .iter()
        .map(|p| CheckReport::new("servo_dac", p, 0))
        .collect()
}

/// `reports` with the cases counted as the cases expected: a contract's
/// coverage is its antecedents' count, which the tests bound below.
fn counted(mut reports: Vec<CheckReport>) -> Vec<CheckReport> {
    for r in &mut reports {
        r.expected = r.covered;
    }
    reports
}

/// The block's checks `motionhdl verify` runs: the model comparison, the
/// contract (each property a row), and with `external` the generated
/// Verilog in Icarus and Verilator.
pub fn all(external: bool) -> Vec<CheckReport> {
    use crate::verilog_sim::Simulator;
    let mut v = vec![
        random_rust(100_000, 0xdac0_0001),
        tour::control_exhaustive(),
        tour::serial_exhaustive(),
    ];
    let trace = run_rust(&stimulus(100_000, 0xdac0_0006));
    v.extend(contract::contract(&trace));
    v.extend(serial::contract(&trace));
    for serial in [false, true] {
        v.push(contract::zero_jitter(
            &contract::servo_run(40, serial),
            serial,
        ));
    }
    if external {
        v.push(random_verilog(Simulator::Icarus, 50_000, 0xdac0_0002));
        v.push(random_verilog(Simulator::Verilator, 500_000, 0xdac0_0003));
    }
    v
}
