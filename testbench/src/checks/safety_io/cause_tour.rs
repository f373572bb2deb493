//! The per-axis cause pairs of one axis, exhaustively: every reachable
//! (state, input) pair of the soft limits (SOFT_LIMIT_CTRL, CAUSE, MASK)
//! and of the counter events (COUNTER_CAUSE, MASK) under both inputs and
//! every bus operation on them, rust-hdl against the model every clock.

use crate::harness::{cycle, settle, CheckReport};
use crate::tour::{explore, tour};
use motionhdl_hdl::axis_causes::AxisCauses as Hdl;
use motionhdl_model::axis_causes::{self as kinds, AxisCauses, CauseKind};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap::{self, Block as Registers};
use rust_hdl::prelude::*;
use std::collections::BTreeSet;

/// One clock's input: at_max, at_min, and the bus operation.
type Input = (bool, bool, u8);

/// Bus operations: idle; CTRL off, low only, high only, both (for a pair
/// without CTRL, SOFT_LIMIT_CTRL: another part's register); W1C low,
/// high, all; MASK 0, all; a read of each register (reads change
/// nothing, but `read_value` is compared after each).
const OPS: u8 = 13;

fn bus(map: &Registers, kind: &CauseKind, op: u8) -> BusCycle {
    let w = |name: &str, v: u32| BusCycle::write(map.register(name).offset, v);
    let r = |name: &str| BusCycle::read(map.register(name).offset);
    let ctrl = kind.ctrl.unwrap_or("SOFT_LIMIT_CTRL");
    match op {
        1 => w(ctrl, 0),
        2 => w(ctrl, 1),
        3 => w(ctrl, 1 << 16),
        4 => w(ctrl, !0),
        5 => w(kind.cause, 1),
        6 => w(kind.cause, 1 << 16),
        7 => w(kind.cause, !0),
        8 => w(kind.mask, 0),
        9 => w(kind.mask, !0),
        10 => r(ctrl),
        11 => r(kind.cause),
        12 => r(kind.mask),
        _ => BusCycle::default(),
    }
}

fn inputs() -> Vec<Input> {
    let b = [false, true];
    b.iter()
        .flat_map(|&x| {
            b.iter()
                .flat_map(move |&n| (0..OPS).map(move |op| (x, n, op)))
        })
        .collect()
}

/// (stop_up, stop_down, irq_active, [CTRL, CAUSE, MASK], the value a
/// read of the op's register returns), after an edge.
type Outputs = (u32, u32, bool, [u32; 3], u32);

fn hdl_outputs(h: &Hdl<1>) -> Outputs {
    (
        h.stop_up.val().index() as u32,
        h.stop_down.val().index() as u32,
        h.irq_active.val(),
        h.probe(),
        h.read_value.val().index() as u32,
    )
}

fn model_outputs(m: &AxisCauses, kind: &CauseKind, map: &Registers, read_addr: u32) -> Outputs {
    let regs = [kind.ctrl, Some(kind.cause), Some(kind.mask)];
    let value = |name: Option<&str>| name.and_then(|n| m.read(n)).unwrap_or(0);
    let read = regs
        .iter()
        .find(|n| n.is_some_and(|n| map.register(n).offset == read_addr))
        .map_or(0, |n| value(*n));
    (
        m.stop_up(),
        m.stop_down(),
        m.irq_active(),
        regs.map(value),
        read,
    )
}

fn clock_hdl(h: &mut Hdl<1>, bus: &BusCycle, &(max, min, _): &Input) {
    h.addr.next = u64::from(super::word_address(bus.addr)).into();
    h.wdata.next = u64::from(bus.wdata).into();
    h.we.next = bus.we;
    h.low.next = u64::from(max).into();
    h.high.next = u64::from(min).into();
    settle(h);
    cycle(h, |h| &mut h.clock);
}

/// The soft limits: see [`exhaustive`].
pub fn soft_limits_exhaustive() -> CheckReport {
    exhaustive(kinds::SOFT_LIMITS)
}

/// The counter events: see [`exhaustive`].
pub fn counter_events_exhaustive() -> CheckReport {
    exhaustive(kinds::COUNTER_EVENTS)
}

/// Every reachable (state, input) pair of one pair of causes from reset.
/// Covered = distinct pairs visited, asserted equal to the pairs
/// enumerated.
fn exhaustive(kind: CauseKind) -> CheckReport {
    let map = regmap::safety_io(1);
    let inputs = inputs();
    let step = |s: &AxisCauses, i: &Input| {
        let mut n = s.clone();
        n.clock(&map, &bus(&map, &kind, i.2), u32::from(i.0), u32::from(i.1));
        n
    };
    let init = AxisCauses::new(1, kind);
    let g = explore(init.clone(), &inputs, step, 1 << 16).expect("a small state space");
    let mut hdl = Hdl::<1>::new(kind);
    hdl.connect_all();
    hdl.reset.next = true;
    settle(&mut hdl);
    cycle(&mut hdl, |h| &mut h.clock);
    hdl.reset.next = false;
    let mut model = init;
    let mut seen = BTreeSet::new();
    let mut failures = Vec::new();
    for (n, k) in tour(&g).into_iter().enumerate() {
        let input = inputs[k];
        seen.insert((model.clone(), k));
        let b = bus(&map, &kind, input.2);
        // The block latches the read address at the `re` edge; the part
        // shows that register's value after it.
        hdl.read_addr.next = u64::from(if b.re { b.addr } else { 0x7f }).into();
        let read_addr = if b.re { b.addr } else { 0x7f };
        model.clock(&map, &b, u32::from(input.0), u32::from(input.1));
        clock_hdl(&mut hdl, &b, &input);
        let (got, want) = (
            hdl_outputs(&hdl),
            model_outputs(&model, &kind, &map, read_addr),
        );
        if got != want {
            failures.push(format!(
                "step {n} input {input:?}: HDL {got:?}, model {want:?}"
            ));
            break;
        }
    }
    let mut r = CheckReport::new(
        "safety_io",
        &format!(
            "one axis's {} (both inputs, 13 bus operations), every reachable state x input",
            kind.cause
        ),
        g.pairs() as u64,
    );
    r.covered = seen.len() as u64;
    r.failures = failures;
    r
}
