//! The DAC interface's control, exhaustively: every reachable (state,
//! input) pair of the transfer sequencer, the request queue, the tick
//! timer and the events under a narrow input alphabet, rust-hdl against
//! the model every clock.
//!
//! Narrow means the inputs, not the widths (the block has none to
//! shrink): the codes stay at their reset value, TICK_PERIOD takes 0 or
//! 3, TIMING gives CS and LOADDACS 1 or 2 clocks, and there are no reads
//! (the random runs read every register). Every control state the block
//! has is reached this way: each phase of each channel with each wait,
//! idle or busy with a request waiting, the tick at every count, the
//! events, the safe input's edge.

use super::{run_rust, Outputs, Vector, CLOCK_HZ};
use crate::harness::CheckReport;
use crate::tour::{explore, tour};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap;
use motionhdl_model::servo_dac::ServoDac as Model;
use std::collections::BTreeSet;

/// A bus operation of an alphabet: idle, or a write of a register.
type Op = (&'static str, u32);

const IDLE: Op = ("", 0);

/// The parallel alphabet: every control state of the parallel interface.
const PARALLEL_OPS: [Op; 7] = [
    IDLE,
    ("UPDATE", 1),
    ("TICK_PERIOD", 0),
    ("TICK_PERIOD", 3),
    ("TIMING", 0),
    ("TIMING", 0x0101),
    ("EVENTS", 3),
];

/// The serial alphabet: SPI with SCLK halves and SYNC's high time of 1
/// clock or 2 (a transfer runs 200 or 400 clocks, so no tick: the tick
/// and the events are the parallel tour's).
const SERIAL_OPS: [Op; 4] = [IDLE, ("UPDATE", 1), ("SERIAL", 1), ("SERIAL", 0x01_0101)];

/// One clock's input: reset, safe, and a bus operation.
type Input = (bool, bool, Op);

fn inputs(ops: &[Op]) -> Vec<Input> {
    let mut v = vec![(true, false, IDLE)];
    for safe in [false, true] {
        v.extend(ops.iter().map(|&op| (false, safe, op)));
    }
    v
}

fn vector(&(reset, safe, (name, value)): &Input) -> Vector {
    let map = regmap::servo_dac(CLOCK_HZ);
    let bus = match name {
        "" => BusCycle::default(),
        name => BusCycle::write(map.register(name).offset, value),
    };
    Vector { reset, bus, safe }
}

fn outputs(m: &Model) -> Outputs {
    Outputs {
        rdata: m.rdata(),
        tick: m.tick(),
        pins: m.pins(),
    }
}

/// Every reachable (state, input) pair from reset under the parallel
/// alphabet. Covered = distinct pairs visited, asserted equal to the
/// pairs enumerated.
pub fn control_exhaustive() -> CheckReport {
    exhaustive("DAC interface control", &PARALLEL_OPS)
}

/// As [`control_exhaustive`], under the serial alphabet.
pub fn serial_exhaustive() -> CheckReport {
    exhaustive("serial DAC interface control", &SERIAL_OPS)
}

fn exhaustive(what: &str, ops: &[Op]) -> CheckReport {
    let inputs = inputs(ops);
    let vectors: Vec<Vector> = inputs.iter().map(vector).collect();
    let step = |s: &Model, k: &usize| {
        let mut n = s.clone();
        let v = vectors[*k];
        n.clock(v.reset, &v.bus, v.safe);
        n
    };
    let init = Model::new(CLOCK_HZ);
    let indices: Vec<usize> = (0..inputs.len()).collect();
    let g = explore(init.clone(), &indices, step, 1 << 20).expect("a bounded state space");
    let walk = tour(&g);
    // The HDL from reset (the model's initial state), then the tour.
    let driven: Vec<Vector> = std::iter::once(vectors[0])
        .chain(walk.iter().map(|&k| vectors[k]))
        .collect();
    let observed = run_rust(&driven);
    let mut r = CheckReport::new(
        "servo_dac",
        &format!(
            "{what} ({} inputs: reset, safe x writes {:?}), every reachable state x input",
            inputs.len(),
            ops
        ),
        g.pairs() as u64,
    );
    let (mut at, mut seen) = (0usize, BTreeSet::new());
    for (n, &k) in walk.iter().enumerate() {
        seen.insert((at, k));
        at = g.next[at][k];
        let (got, want) = (observed[n + 1].outputs, outputs(&g.states[at]));
        if got != want {
            r.failures.push(format!(
                "step {n} input {:?}: HDL {got:?}, model {want:?}",
                inputs[k]
            ));
            break;
        }
    }
    r.covered = seen.len() as u64;
    r
}
