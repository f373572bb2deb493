//! Move engine checks: the segment FIFO in block RAM against the model
//! every clock, and its contract stated on the HDL alone (Amaranth's FIFO
//! split): order and contents, level, full and overflow, empty, wrap,
//! low-water and the copy's latency, each with a coverage count.

use crate::harness::{cycle, settle, CheckReport, Rng};
use crate::state_map;
use motionhdl_hdl::MoveEngine;
use motionhdl_model::pulse_generator::{
    self as m, SegmentField, SEGMENT_FETCH_CLOCKS, SEGMENT_FIFO_DEPTH,
};
use motionhdl_model::pulse_generator::{ACCEL_FRAC_BITS, LOAD_FRACTION, RAMP_BITS};
use motionhdl_model::regmap;
use rust_hdl::prelude::Block;
use std::collections::VecDeque;

/// One clock of the engine's inputs.
#[derive(Clone, Copy, Debug, Default)]
pub struct EngineInputs {
    pub reset: bool,
    pub run: bool,
    pub commanded: bool,
    pub advancing: bool,
    pub write: Option<(SegmentField, u32)>,
    pub push: bool,
    pub clear_overflow: bool,
    pub low_water: u32,
    /// A decelerating stop at this edge: (the NCO's rate, DECEL).
    pub brake: Option<(i32, u32)>,
}

/// What the contract sees of the HDL around one edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EngineView {
    pub active: bool,
    /// The BRAKING output.
    pub braking: bool,
    pub level: u32,
    pub overflow: bool,
    /// STATUS.FIFO_LEVEL and FIFO_LOW as the engine drives them.
    pub status_level: u32,
    pub status_low: bool,
    /// The head copy is complete (a pop takes it).
    pub staged: bool,
    /// The running segment's registers: remaining, rate and acceleration
    /// (48 bits with their fractions), jerk.
    pub running: [u64; 4],
}

/// Random traffic in phases of 3000 clocks: fill (RUN low, segments pushed
/// back to back, then pushes and writes into the full FIFO), drain (RUN
/// high, steps commanded often), and mixed; short segments (0..=6 steps)
/// so the head wraps many times; the low-water mark moves; rare resets;
/// a decelerating stop about every 4000 clocks (rates up to ±20 000, DECEL
/// 8 to 71 LSB a clock, so each brake ends within about 5000 clocks).
pub fn engine_stimulus(clocks: usize, seed: u64) -> Vec<EngineInputs> {
    let mut rng = Rng::new(seed);
    let mut v = vec![
        EngineInputs {
            reset: true,
            ..Default::default()
        };
        4
    ];
    let mut low_water = 8;
    let mut field = 0;
    while v.len() < clocks {
        let phase = (v.len() / 3000) % 3;
        if rng.below(500) == 0 {
            low_water = rng.below(SEGMENT_FIFO_DEPTH as u64 + 2) as u32;
        }
        let mut inp = EngineInputs {
            run: phase != 0 || rng.below(8) == 0,
            commanded: rng.below(if phase == 1 { 2 } else { 4 }) == 0,
            advancing: rng.below(2) == 0,
            clear_overflow: rng.below(700) == 0,
            low_water,
            reset: rng.below(20_000) == 0,
            ..Default::default()
        };
        if rng.below(4000) == 0 {
            let rate = rng.below(40_001) as i32 - 20_000;
            inp.brake = Some((rate, ((8 + rng.below(64)) as u32) << 16));
        }
        let busy = if phase == 1 { 40 } else { 2 };
        if rng.below(busy) == 0 {
            if field < 4 {
                let (f, value) = match field {
                    0 => (SegmentField::Steps, rng.below(7) as u32),
                    1 => (SegmentField::Rate, rng.next_u64() as u32),
                    2 => (SegmentField::Accel, rng.next_u64() as u32),
                    _ => (SegmentField::Jerk, rng.next_u64() as u32),
                };
                inp.write = Some((f, value));
                // Now and then a field is left out: the slot's old word.
                field += if rng.below(30) == 0 { 2 } else { 1 };
            } else {
                inp.push = true;
                field = 0;
            }
        }
        v.push(inp);
    }
    v.truncate(clocks);
    v
}

/// The contract, from inputs and views alone: a scoreboard of pushed
/// segments (contents known when all four fields were written since the
/// last accepted push, while there was room), and coverage counts.
#[derive(Debug, Default)]
pub struct FifoContract {
    queue: VecDeque<Option<[u32; 4]>>,
    written: [Option<u32>; 4],
    waiting: usize,
    pub pops: u64,
    pub checked_pops: u64,
    pub full_pushes: u64,
    pub empty_stalls: u64,
    pub low_changes: u64,
    /// Decelerating stops, and clocks spent braking.
    pub brakes: u64,
    pub braking_clocks: u64,
    last_low: bool,
}

impl FifoContract {
    /// Checks one edge: `before` with the inputs applied, `after` the edge.
    pub fn edge(
        &mut self,
        inp: &EngineInputs,
        before: &EngineView,
        after: &EngineView,
    ) -> Option<String> {
        let depth = SEGMENT_FIFO_DEPTH as u32;
        let mut bad = Vec::new();
        if before.status_level != before.level || before.level > depth {
            bad.push(format!(
                "FIFO_LEVEL {} for level {}",
                before.status_level, before.level
            ));
        }
        if before.status_low != (before.level <= inp.low_water) {
            bad.push(format!(
                "FIFO_LOW {} at level {} mark {}",
                before.status_low, before.level, inp.low_water
            ));
        }
        if before.status_low != self.last_low {
            self.low_changes += 1;
            self.last_low = before.status_low;
        }
        if inp.reset {
            self.queue.clear();
            self.written = [None; 4];
            self.waiting = 0;
            if *after
                != (EngineView {
                    status_low: after.status_low,
                    ..Default::default()
                })
            {
                bad.push(format!("after reset: {after:?}"));
            }
            return (!bad.is_empty()).then(|| bad.join("; "));
        }
        self.braking_clocks += u64::from(before.braking);
        // A brake drops the head copy with the rest (below): not a load.
        let popped = before.staged && !after.staged && inp.brake.is_none();
        if popped {
            self.pops += 1;
            if before.active || !inp.run || before.braking {
                bad.push(format!(
                    "a segment loaded while {}",
                    if before.active {
                        "one ran"
                    } else if before.braking {
                        "braking"
                    } else {
                        "RUN was low"
                    }
                ));
            }
            match self.queue.pop_front() {
                None => bad.push("a segment loaded from an empty FIFO".into()),
                Some(Some(want)) => {
                    self.checked_pops += 1;
                    // The jerk shows while the segment runs (a zero-step
                    // one is over at once).
                    let mut expected = loaded(want);
                    if !after.active {
                        expected[3] = 0;
                    }
                    if after.running != expected {
                        bad.push(format!(
                            "loaded (steps, rate, accel, jerk) {:?}, pushed {want:?}",
                            after.running
                        ));
                    }
                }
                Some(None) => {}
            }
        }
        // A segment waiting with RUN high and nothing running or braking
        // loads within the copy's latency.
        if inp.run && !before.active && !before.braking && !self.queue.is_empty() && !popped {
            self.waiting += 1;
            self.empty_stalls += u64::from(self.waiting == 1);
            if self.waiting > SEGMENT_FETCH_CLOCKS + 1 {
                bad.push(format!("a segment waited {} clocks to load", self.waiting));
            }
        } else {
            self.waiting = 0;
        }
        let room = (self.queue.len() as u32) < depth;
        if let Some((f, value)) = inp.write.filter(|_| room) {
            self.written[f as usize] = Some(value);
        }
        if inp.push {
            if room {
                let [s, r, a, j] = self.written;
                self.queue
                    .push_back(s.zip(r).zip(a.zip(j)).map(|((s, r), (a, j))| [s, r, a, j]));
                self.written = [None; 4];
            } else {
                self.full_pushes += 1;
            }
        }
        // OVERFLOW: set by a push into the full FIFO, kept, cleared by
        // clear_overflow (which wins in the same clock).
        let rejected = inp.push && !room;
        if after.overflow != ((before.overflow || rejected) && !inp.clear_overflow) {
            bad.push(format!(
                "OVERFLOW {} after {}",
                after.overflow,
                if rejected {
                    "a push into the full FIFO"
                } else {
                    "an edge without one"
                }
            ));
        }
        // A brake drops every queued segment (this edge's push too) and
        // the tail moves to the head: fields written so far are unknown.
        if inp.brake.is_some() {
            self.brakes += 1;
            self.queue.clear();
            self.written = [None; 4];
        }
        if after.level != self.queue.len() as u32 {
            bad.push(format!(
                "level {} with {} segments queued",
                after.level,
                self.queue.len()
            ));
        }
        (!bad.is_empty()).then(|| bad.join("; "))
    }
}

/// The running registers a pushed segment loads as: the rate and the
/// acceleration get 16 fraction bits holding half an LSB (48 bits, two's
/// complement).
pub fn loaded([steps, rate, accel, jerk]: [u32; 4]) -> [u64; 4] {
    let wide = |x: u32| {
        (((i64::from(x as i32) << ACCEL_FRAC_BITS) + LOAD_FRACTION) as u64) & ((1 << RAMP_BITS) - 1)
    };
    [steps.into(), wide(rate), wide(accel), jerk.into()]
}

fn apply(uut: &mut MoveEngine, inp: &EngineInputs) {
    let write = |f: SegmentField| inp.write.is_some_and(|(g, _)| g == f);
    uut.reset.next = inp.reset;
    uut.run.next = inp.run;
    uut.commanded.next = inp.commanded;
    uut.advancing.next = inp.advancing;
    uut.push.next = inp.push;
    uut.wdata.next = u64::from(inp.write.map_or(0, |w| w.1)).into();
    uut.write_steps.next = write(SegmentField::Steps);
    uut.write_rate.next = write(SegmentField::Rate);
    uut.write_accel.next = write(SegmentField::Accel);
    uut.write_jerk.next = write(SegmentField::Jerk);
    uut.clear_overflow.next = inp.clear_overflow;
    uut.low_water.next = u64::from(inp.low_water).into();
    let (rate, decel) = inp.brake.unwrap_or_default();
    uut.brake.next = inp.brake.is_some();
    uut.brake_rate.next = u64::from(rate as u32).into();
    uut.decel.next = u64::from(decel).into();
}

/// The engine's fields of STATUS, as the register map places them (BUSY
/// and PENDING are the generator's).
const ENGINE_STATUS: [&str; 6] = [
    "MOVING",
    "DONE",
    "OVERFLOW",
    "FIFO_LEVEL",
    "FIFO_LOW",
    "BRAKING",
];

/// Each of [`ENGINE_STATUS`] as (lsb, mask).
fn engine_status_fields() -> [(u32, u32); 6] {
    let map = regmap::pulse_bank(1, 32);
    let status = map.array("AX").register("STATUS");
    ENGINE_STATUS.map(|name| {
        let f = status.field(name);
        (f.lsb, (1 << f.width) - 1)
    })
}

/// The engine's part of STATUS as the model's state gives it.
fn model_status(model: &m::MoveEngine, low_water: u32, fields: &[(u32, u32); 6]) -> u32 {
    let level = model.level() as u32;
    [
        u32::from(model.active()),
        u32::from(model.done()),
        u32::from(model.overflow()),
        level,
        u32::from(level <= low_water),
        u32::from(model.braking()),
    ]
    .iter()
    .zip(fields)
    .fold(0, |w, (v, (lsb, _))| w | v << lsb)
}

fn view(uut: &MoveEngine, fields: &[(u32, u32); 6]) -> EngineView {
    let [_, _, _, level, low, _] = *fields;
    let s = uut.status.val().index() as u32;
    let p = uut.probe();
    EngineView {
        active: p.active,
        braking: uut.braking.val(),
        level: p.level,
        overflow: p.overflow,
        status_level: s >> level.0 & level.1,
        status_low: s >> low.0 & low.1 == 1,
        staged: p.staged,
        running: [p.remaining.into(), p.rate, p.accel, p.jerk.into()],
    }
}

/// The rust-hdl engine against the model every clock (every register,
/// the copy's progress included, the RATE and BRAKING outputs and its
/// STATUS bits), and
/// the contract on the HDL alone.
/// Cases: one per clock; the coverage counts must all be reached.
pub fn engine_rust(clocks: usize, seed: u64) -> CheckReport {
    let mut r = CheckReport::new(
        "pulse_generator",
        &format!("move engine, {clocks} clocks: rust-hdl vs model, and the FIFO contract"),
        clocks as u64,
    );
    let mut uut = MoveEngine::new();
    uut.connect_all();
    let mut model = m::MoveEngine::default();
    let mut contract = FifoContract::default();
    let fields = engine_status_fields();
    for (k, inp) in engine_stimulus(clocks, seed).iter().enumerate() {
        apply(&mut uut, inp);
        settle(&mut uut);
        let before = view(&uut, &fields);
        // STATUS is combinational from the registers: compared before the
        // edge, with the model's state before its clock.
        let status = (
            uut.status.val().index() as u32,
            model_status(&model, inp.low_water, &fields),
        );
        cycle(&mut uut, |u| &mut u.clock);
        if inp.reset {
            model.reset();
        } else {
            let writes: Vec<_> = inp.write.into_iter().collect();
            let was_braking = model.braking();
            model.clock_bus(inp.run, inp.commanded, inp.advancing, &writes, inp.push);
            if let Some((rate, decel)) = inp.brake {
                model.brake(was_braking, rate, decel);
            }
            if inp.clear_overflow {
                model.clear_overflow();
            }
        }
        let got = state_map::engine(uut.probe());
        let outputs = (uut.rate.val().index() as u32 as i32, uut.braking.val());
        let want = (model.rate(), model.braking());
        let mut bad = (got != model.probe())
            .then(|| format!("clock {k} {inp:?}: HDL {got:?}, model {:?}", model.probe()))
            .or_else(|| {
                (outputs != want).then(|| {
                    format!("clock {k} {inp:?}: (rate, braking) HDL {outputs:?}, model {want:?}")
                })
            })
            .or_else(|| {
                (status.0 != status.1).then(|| {
                    format!(
                        "clock {k} {inp:?}: STATUS HDL {:#x}, model {:#x}",
                        status.0, status.1
                    )
                })
            });
        if let Some(b) = contract.edge(inp, &before, &view(&uut, &fields)) {
            bad.get_or_insert(format!("clock {k} {inp:?}: contract: {b}"));
        }
        r.case(bad);
    }
    let wraps = contract.pops / SEGMENT_FIFO_DEPTH as u64;
    for (what, n, least) in [
        ("loads", contract.pops, 4 * SEGMENT_FIFO_DEPTH as u64),
        (
            "loads with known contents",
            contract.checked_pops,
            SEGMENT_FIFO_DEPTH as u64,
        ),
        ("pushes into a full FIFO", contract.full_pushes, 10),
        ("waits for the head copy", contract.empty_stalls, 10),
        ("FIFO_LOW changes", contract.low_changes, 10),
        ("head wraps", wraps, 3),
        ("decelerating stops", contract.brakes, 5),
        ("clocks braking", contract.braking_clocks, 1000),
    ] {
        if n < least {
            r.failures
                .push(format!("coverage: {n} {what}, want at least {least}"));
        }
    }
    r
}

/// The move engine's checks `motionhdl verify` runs.
pub fn all(_external: bool) -> Vec<CheckReport> {
    vec![engine_rust(60_000, 0x5eed_0018)]
}
