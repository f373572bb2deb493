//! The stop logic of one axis, exhaustively: every reachable (state,
//! input) pair of the one-axis machine inputs (LIMIT_POS and ALARM pins,
//! their filters on a two-clock tick, the causes and the stops), for
//! every enable and polarity of the two inputs, rust-hdl against the model
//! every clock.

use crate::harness::{cycle, settle, CheckReport};
use crate::tour::{explore, tour};
use motionhdl_hdl::machine_inputs::MachineStops as Hdl;
use motionhdl_model::counter::BusCycle;
use motionhdl_model::machine_inputs::{MachinePins, MachineStops};
use motionhdl_model::regmap::{self, Block as Registers};
use rust_hdl::prelude::*;
use std::collections::BTreeSet;

/// The tour's filter tick: two clocks, so clocks without a tick are in it.
const TICK: u32 = 2;

/// One clock's input: LIMIT_POS and ALARM pins, and the bus: 0 idle,
/// 1 all 1s written to LIMIT_CAUSE, 2 to HOME_ALARM_CAUSE.
type Input = (bool, bool, u8);

fn inputs() -> Vec<Input> {
    let b = [false, true];
    b.iter()
        .flat_map(|&p| b.iter().flat_map(move |&a| (0..3).map(move |c| (p, a, c))))
        .collect()
}

fn bus(map: &Registers, op: u8) -> BusCycle {
    match op {
        1 => BusCycle::write(map.register("LIMIT_CAUSE").offset, !0),
        2 => BusCycle::write(map.register("HOME_ALARM_CAUSE").offset, !0),
        _ => BusCycle::default(),
    }
}

fn pins(&(pos, alarm, _): &Input) -> MachinePins {
    MachinePins {
        limit_pos: u32::from(pos),
        alarm: u32::from(alarm),
        ..Default::default()
    }
}

/// The HDL's outputs after an edge: (stop_up, stop_down, irq_active,
/// LIMIT_CAUSE, HOME_ALARM_CAUSE).
fn hdl_outputs(h: &Hdl<1>) -> (u32, u32, bool, u32, u32) {
    let (_, _, [limit, _, home_alarm, _]) = h.probe();
    (
        h.stop_up.val().index() as u32,
        h.stop_down.val().index() as u32,
        h.irq_active.val(),
        limit,
        home_alarm,
    )
}

fn model_outputs(m: &MachineStops) -> (u32, u32, bool, u32, u32) {
    (
        m.stop_up(),
        m.stop_down(),
        m.irq_active(),
        m.read("LIMIT_CAUSE").unwrap(),
        m.read("HOME_ALARM_CAUSE").unwrap(),
    )
}

fn clock_hdl(h: &mut Hdl<1>, bus: &BusCycle, input: &Input) {
    let p = pins(input);
    h.addr.next = u64::from(super::word_address(bus.addr)).into();
    h.wdata.next = u64::from(bus.wdata).into();
    h.we.next = bus.we;
    h.limit_pos.next = u64::from(p.limit_pos).into();
    h.alarm.next = u64::from(p.alarm).into();
    settle(h);
    cycle(h, |h| &mut h.clock);
}

/// Every reachable (state, input) pair for each of the 16 settings of
/// LIMIT_POS_CTRL and ALARM_CTRL (enable, polarity). Covered = distinct
/// pairs visited, asserted equal to the pairs enumerated.
pub fn stops_exhaustive() -> CheckReport {
    let map = regmap::safety_io(1);
    let inputs = inputs();
    let (mut expected, mut covered) = (0u64, 0u64);
    let mut failures = Vec::new();
    for setting in 0u32..16 {
        // Bits 0/1: LIMIT_POS enable/active-low; 2/3: ALARM's.
        let ctrl = |b: u32| (setting >> b & 1) | (setting >> (b + 1) & 1) << 16;
        let writes = [
            BusCycle::write(map.register("LIMIT_POS_CTRL").offset, ctrl(0)),
            BusCycle::write(map.register("ALARM_CTRL").offset, ctrl(2)),
            BusCycle::write(map.register("LIMIT_MASK").offset, 1),
        ];
        let mut init = MachineStops::new(1, TICK);
        let mut hdl = Hdl::<1>::new(TICK);
        hdl.connect_all();
        hdl.reset.next = true;
        settle(&mut hdl);
        cycle(&mut hdl, |h| &mut h.clock);
        hdl.reset.next = false;
        let idle = (false, false, 0);
        for w in &writes {
            init.clock(&map, w, &pins(&idle));
            clock_hdl(&mut hdl, w, &idle);
        }
        let step = |s: &MachineStops, i: &Input| {
            let mut n = s.clone();
            n.clock(&map, &bus(&map, i.2), &pins(i));
            n
        };
        let g = explore(init.clone(), &inputs, step, 1 << 18).expect("a small state space");
        expected += g.pairs() as u64;
        let mut model = init;
        let mut seen = BTreeSet::new();
        for (n, k) in tour(&g).into_iter().enumerate() {
            let input = inputs[k];
            seen.insert((model.clone(), k));
            model.clock(&map, &bus(&map, input.2), &pins(&input));
            clock_hdl(&mut hdl, &bus(&map, input.2), &input);
            let (got, want) = (hdl_outputs(&hdl), model_outputs(&model));
            if got != want {
                failures.push(format!(
                    "setting {setting:#06b} step {n} input {input:?}: HDL {got:?}, model {want:?}"
                ));
                break;
            }
        }
        covered += seen.len() as u64;
    }
    let mut r = CheckReport::new(
        "safety_io",
        "one axis's stop logic (LIMIT_POS, ALARM, filters on a 2-clock tick, causes, stops), every \
         reachable state x input, 16 enable/polarity settings",
        expected,
    );
    r.covered = covered;
    r.failures = failures;
    r
}
