//! Safety and I/O block checks: the block against its model every clock
//! under random register traffic, e-stop episodes and move events (in
//! rust-hdl and as generated Verilog), and its contract, stated apart
//! from the model (docs/safety_io.md).

pub mod cause_tour;
pub mod contract;
pub mod tour;

use crate::harness::{cycle, random_bus_cycle, settle, CheckReport, Rng};
use crate::verilog_sim::{compare_clocked, ports_of, sim_failure, Design, Target};
use motionhdl_hdl::probe::SafetyRegisters;
use motionhdl_hdl::{catalog, SafetyIo};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::digital_io::{GpoPins, GPIO_INPUTS};
use motionhdl_model::machine_inputs::MachinePins;
use motionhdl_model::regmap;
use motionhdl_model::safety_io::{SafetyInputs, SafetyIo as Model, WATCHDOG_KEY};
use rust_hdl::prelude::*;

/// Axes of the instance the checks run.
pub const AXES: usize = 4;

/// The machine inputs' filter tick of the instance the checks run: short,
/// so random pins pass the filter and glitches of a few clocks do not.
pub const TICK_CLOCKS: u32 = 2;

/// `addr` as the block decodes it: its word address bits.
pub fn word_address(addr: u32) -> u32 {
    addr & ((1 << motionhdl_hdl::safety_io::SAFETY_ADDRESS_BITS) - 1)
}

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
    pub stop_up: u32,
    pub stop_down: u32,
    pub home_event: u32,
    pub gpo: GpoPins,
}

fn write_data(register: &str, next: &mut dyn FnMut() -> u64) -> u32 {
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
        ..Default::default()
    };
    let mut estop_low_for = 0;
    // Machine and general-purpose input pins: levels that hold for a few
    // hundred clocks, and glitches of one to eight clocks on top of them.
    let mut levels = [0u32; 5];
    let mut glitch = [0u32; 5];
    let mut glitch_for = 0;
    let some_pin = |next: &mut dyn FnMut() -> u64| {
        let kind = (next() % 5) as usize;
        let width = if kind == 4 { GPIO_INPUTS } else { AXES as u32 };
        (kind, 1 << (next() % u64::from(width)))
    };
    while v.len() < clocks {
        if next().is_multiple_of(16) {
            let (kind, bit) = some_pin(&mut next);
            levels[kind] ^= bit;
        }
        if glitch_for == 0 && next().is_multiple_of(64) {
            glitch_for = 1 + next() % 8;
            glitch = [0; 5];
            let (kind, bit) = some_pin(&mut next);
            glitch[kind] = bit;
        }
        let pins: Vec<u32> = (0..5)
            .map(|k| levels[k] ^ if glitch_for > 0 { glitch[k] } else { 0 })
            .collect();
        glitch_for = glitch_for.saturating_sub(1);
        inputs.machine = MachinePins {
            limit_pos: pins[0],
            limit_neg: pins[1],
            home: pins[2],
            alarm: pins[3],
            gpi: pins[4],
        };
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
        // The pulse bank's soft-limit comparisons come and go per axis.
        if next().is_multiple_of(32) {
            inputs.at_soft_max ^= 1 << (next() % AXES as u64);
        }
        if next().is_multiple_of(32) {
            inputs.at_soft_min ^= 1 << (next() % AXES as u64);
        }
        // The counter channels' STATUS.ERR and SEEN flags likewise.
        if next().is_multiple_of(32) {
            inputs.counter_error ^= 1 << (next() % AXES as u64);
        }
        if next().is_multiple_of(32) {
            inputs.index_seen ^= 1 << (next() % AXES as u64);
        }
        // The ISA bridge's doorbell and the servo tick: one-clock pulses
        // (one draw for both, so the other inputs' stream is unchanged).
        let ring = next() % 64;
        inputs.doorbell = ring == 0;
        inputs.servo_tick = ring == 1;
        let bus = random_bus_cycle(&map, 6, &mut next, write_data);
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
    let mut model = Model::new(AXES as u32, TICK_CLOCKS);
    vectors
        .iter()
        .map(|v| {
            model.clock(v.reset, &v.bus, &v.inputs);
            Outputs {
                rdata: model.rdata(),
                halt: model.halted(),
                drive_enable: model.drive_enable(),
                irq: model.irq_pin(),
                stop_up: model.stop_up(),
                stop_down: model.stop_down(),
                home_event: model.home_event(),
                gpo: model.gpo_pins(),
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
    let mut uut = SafetyIo::<AXES>::new(TICK_CLOCKS);
    uut.connect_all();
    vectors
        .iter()
        .map(|v| {
            uut.reset.next = v.reset;
            uut.addr.next = u64::from(word_address(v.bus.addr)).into();
            uut.wdata.next = u64::from(v.bus.wdata).into();
            uut.we.next = v.bus.we;
            uut.re.next = v.bus.re;
            uut.estop_ok.next = v.inputs.estop_ok;
            uut.done.next = u64::from(v.inputs.done).into();
            uut.low.next = u64::from(v.inputs.low).into();
            let m = v.inputs.machine;
            uut.limit_pos.next = u64::from(m.limit_pos).into();
            uut.limit_neg.next = u64::from(m.limit_neg).into();
            uut.home.next = u64::from(m.home).into();
            uut.alarm.next = u64::from(m.alarm).into();
            uut.gpi.next = u64::from(m.gpi).into();
            uut.at_soft_max.next = u64::from(v.inputs.at_soft_max).into();
            uut.at_soft_min.next = u64::from(v.inputs.at_soft_min).into();
            uut.counter_error.next = u64::from(v.inputs.counter_error).into();
            uut.index_seen.next = u64::from(v.inputs.index_seen).into();
            uut.doorbell.next = v.inputs.doorbell;
            uut.servo_tick.next = v.inputs.servo_tick;
            settle(&mut uut);
            cycle(&mut uut, |u| &mut u.clock);
            Observed {
                vector: *v,
                outputs: Outputs {
                    rdata: uut.rdata.val().index() as u32,
                    halt: uut.halt.val(),
                    drive_enable: uut.drive_enable.val().index() as u32,
                    irq: uut.irq.val(),
                    stop_up: uut.stop_up.val().index() as u32,
                    stop_down: uut.stop_down.val().index() as u32,
                    home_event: uut.home_event.val().index() as u32,
                    gpo: GpoPins {
                        out: uut.gpo_out.val().index() as u32,
                        oe: uut.gpo_oe.val().index() as u32,
                    },
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
    let r = CheckReport::new(
        "safety_io",
        &format!(
            "{AXES} axes, {clocks} random clocks: {} vs model",
            target.describe()
        ),
        clocks as u64,
    );
    let vectors = stimulus(clocks, seed);
    let want = model_outputs(&vectors);
    let module = catalog::safety_io(AXES as u32, TICK_CLOCKS);
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
                "reset",
                "addr",
                "wdata",
                "we",
                "re",
                "estop_ok",
                "done",
                "low",
                "limit_pos",
                "limit_neg",
                "home",
                "alarm",
                "gpi",
                "at_soft_max",
                "at_soft_min",
                "counter_error",
                "index_seen",
                "doorbell",
                "servo_tick",
            ],
        ),
        outputs: ports_of(
            &module,
            &[
                "rdata",
                "halt",
                "drive_enable",
                "irq",
                "stop_up",
                "stop_down",
                "home_event",
                "gpo_out",
                "gpo_oe",
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
                u64::from(v.inputs.estop_ok),
                u64::from(v.inputs.done),
                u64::from(v.inputs.low),
            ]
            .into_iter()
            .chain(v.inputs.machine.kinds().map(u64::from))
            .chain([
                u64::from(v.inputs.machine.gpi),
                u64::from(v.inputs.at_soft_max),
                u64::from(v.inputs.at_soft_min),
                u64::from(v.inputs.counter_error),
                u64::from(v.inputs.index_seen),
                u64::from(v.inputs.doorbell),
                u64::from(v.inputs.servo_tick),
            ])
            .collect()
        })
        .collect();
    let want: Vec<Vec<u64>> = want
        .iter()
        .map(|w| {
            vec![
                u64::from(w.rdata),
                u64::from(w.halt),
                u64::from(w.drive_enable),
                u64::from(w.irq),
                u64::from(w.stop_up),
                u64::from(w.stop_down),
                u64::from(w.home_event),
                u64::from(w.gpo.out),
                u64::from(w.gpo.oe),
            ]
        })
        .collect();
    compare_clocked(r, target, &design, rows, &want, |k| {
        format!("{:?}", vectors[k])
    })
}

/// The block's checks `motionhdl verify` runs: the model comparison, the
/// contract (each property a row), and with `external` the generated
/// Verilog in Icarus and Verilator.
pub fn all(external: bool) -> Vec<CheckReport> {
    use crate::verilog_sim::Simulator;
    let mut v = vec![
        random_rust(100_000, 0x5afe_0001),
        tour::stops_exhaustive(),
        cause_tour::soft_limits_exhaustive(),
        cause_tour::counter_events_exhaustive(),
    ];
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
