//! Pulse generator checks: the step timer exhaustively at a narrow instance
//! (every reachable state × every request × every timing 0..=2), the whole
//! axis against the model every clock under random rates, reversals and
//! timing changes (rust-hdl, and the generated Verilog in Icarus and
//! Verilator), and contract properties of the emitted waveform. The bank
//! of axes is checked in [`crate::checks::pulse_bank`].

use crate::harness::{cycle, settle, CheckReport, Rng};
use crate::state_map;
use crate::tour;
use crate::verilog_sim::{ports_of, run_vectors, Design, Simulator, Target};
use motionhdl_hdl::{catalog, PulseGenerator, StepTimer};
use motionhdl_model::pulse_generator::{
    self as m, PulseInputs, Request, StepTimer as ModelTimer, StepTimerState, StepTiming,
};
use rust_hdl::prelude::*;

/// The exhaustive instance: a 3-bit queue (±3) and 3-bit timers.
pub const NARROW_P: usize = 3;
pub const NARROW_T: usize = 3;
/// Timing values the exhaustive check applies (each of the four).
pub const NARROW_TIMINGS: u32 = 3;

/// One input of the exhaustive check: a request, the timing, and whether
/// the queue is flushed (the safety block's HALT).
pub type NarrowInput = (Request, StepTiming, bool);

/// Every (request, timing, flush) input of the exhaustive check.
pub fn narrow_inputs() -> Vec<NarrowInput> {
    let mut v = Vec::new();
    let n = NARROW_TIMINGS;
    for flush in [false, true] {
        for request in [Request::None, Request::Up, Request::Down] {
            for code in 0..n.pow(4) {
                let d = |k: u32| (code / n.pow(k)) % n;
                let timing = StepTiming {
                    step_len: d(0),
                    step_space: d(1),
                    dir_setup: d(2),
                    dir_hold: d(3),
                };
                v.push((request, timing, flush));
            }
        }
    }
    v
}

/// The model's successor; a request the queue refuses becomes none (the
/// NCO would hold).
fn narrow_step(s: &StepTimerState, inp: &NarrowInput) -> StepTimerState {
    let mut t = ModelTimer::new(NARROW_P as u32, NARROW_T as u32);
    t.set_state(*s);
    let request = if t.accepts(inp.0) {
        inp.0
    } else {
        Request::None
    };
    t.clock_flushing(request, &inp.1, inp.2);
    t.state()
}

/// Every reachable (state, input) pair of the narrow step timer, driven as
/// one transition tour through the rust-hdl block and compared with the
/// model every clock (every register and every output). Returns the report
/// (covered = pairs visited) and the number of pairs enumerated.
pub fn exhaustive_timer() -> (CheckReport, u64) {
    let inputs = narrow_inputs();
    let init = ModelTimer::new(NARROW_P as u32, NARROW_T as u32).state();
    let g = tour::explore(init, &inputs, narrow_step, 10_000).expect("state space");
    let pairs = g.pairs() as u64;
    let mut r = CheckReport::new(
        "pulse_generator",
        &format!(
            "step timer P={NARROW_P} T={NARROW_T}, every reachable state x request x timing 0..={} x flush: rust-hdl vs model",
            NARROW_TIMINGS - 1
        ),
        pairs,
    );
    let path = tour::tour(&g);
    let mut uut = StepTimer::<NARROW_P, NARROW_T>::new();
    uut.connect_all();
    // Reset into the initial state.
    uut.reset.next = true;
    settle(&mut uut);
    cycle(&mut uut, |u| &mut u.clock);
    uut.reset.next = false;
    let mut model = ModelTimer::new(NARROW_P as u32, NARROW_T as u32);
    let mut visited = std::collections::BTreeSet::new();
    let mut at = 0usize;
    for (k, &i) in path.iter().enumerate() {
        let (req, timing, flush) = inputs[i];
        let request = if model.accepts(req) {
            req
        } else {
            Request::None
        };
        uut.request_up.next = request == Request::Up;
        uut.request_down.next = request == Request::Down;
        uut.flush.next = flush;
        uut.step_len.next = u64::from(timing.step_len).into();
        uut.step_space.next = u64::from(timing.step_space).into();
        uut.dir_setup.next = u64::from(timing.dir_setup).into();
        uut.dir_hold.next = u64::from(timing.dir_hold).into();
        settle(&mut uut);
        // A step S1 starts shows in the `emitted` register after the edge.
        let leave = model.leaving();
        let room = (model.has_room(Request::Up), model.has_room(Request::Down));
        let got_comb = (
            (uut.leave_up.val(), uut.leave_down.val()),
            (uut.room_up.val(), uut.room_down.val()),
        );
        let want_comb = ((leave > 0, leave < 0), room);
        let before = model.state();
        model.clock_flushing(request, &timing, flush);
        cycle(&mut uut, |u| &mut u.clock);
        let got = state_map::step_timer(uut.probe());
        let want = model.state();
        let fresh = visited.insert((at, i));
        at = g.next[at][i];
        if want != g.states[at] {
            r.failures
                .push(format!("tour and model disagree at step {k}"));
            break;
        }
        let bad = got != want || got_comb != want_comb;
        if fresh {
            r.case(bad.then(|| {
                format!(
                    "from {before:?} with {request:?} {timing:?} flush {flush}: HDL {got:?} {got_comb:?}, model {want:?} {want_comb:?}"
                )
            }));
        } else if bad {
            r.failures
                .push(format!("revisit at step {k}: HDL {got:?}, model {want:?}"));
        }
        if r.failures.len() > 5 {
            break;
        }
    }
    (r, pairs)
}

/// One clock of stimulus for the whole axis.
#[derive(Clone, Copy, Debug)]
pub struct Vector {
    pub reset: bool,
    pub inputs: PulseInputs,
}

/// Random axis stimulus: segments of constant rate (slow, fast up to f/2,
/// zero, reversals), timing changes, enable gaps, and a reset or two.
pub fn stimulus(clocks: usize, seed: u64) -> Vec<Vector> {
    let mut next = Rng::stream(seed);
    let mut v = vec![
        Vector {
            reset: true,
            inputs: PulseInputs::default()
        };
        4
    ];
    let mut inputs = PulseInputs {
        enable: true,
        halt: false,
        rate: 0,
        timing: StepTiming::default(),
    };
    while v.len() < clocks {
        let len = 1 + (next() % 400) as usize;
        inputs.rate = match next() % 8 {
            0 => 0,
            1 => i32::MIN,
            2 => i32::MAX,
            3 => -(next() as i32 >> (next() % 8)).abs(),
            _ => (next() as i32) >> (2 + next() % 14),
        };
        if next().is_multiple_of(4) {
            let t = |n: u64| (n % 6) as u32;
            inputs.timing = StepTiming {
                step_len: t(next()),
                step_space: t(next()),
                dir_setup: t(next()),
                dir_hold: t(next()),
            };
        }
        inputs.enable = !next().is_multiple_of(8);
        let reset = next().is_multiple_of(200);
        // A HALT now and then, from one clock to a few, mid-motion.
        let halt_for = if next().is_multiple_of(6) {
            1 + next() % 8
        } else {
            0
        };
        for k in 0..len {
            inputs.halt = (k as u64) < halt_for;
            v.push(Vector {
                reset: reset && k < 4,
                inputs,
            });
        }
    }
    v.truncate(clocks);
    v
}

/// The axis's output pins as the model has them: (S1, S2, position,
/// STATUS), STATUS being PENDING (PENDING_BITS-bit two's complement) in
/// 15:0 and BUSY in 16.
fn pins_of(g: &m::PulseGenerator) -> (bool, bool, u32, u32) {
    let (s, d) = g.outputs();
    let pending = g.timer.state().pending as u32 & ((1u32 << m::PENDING_BITS) - 1);
    (s, d, g.position, pending | u32::from(g.busy()) << 16)
}

/// The model through `vectors`: [`pins_of`] after every clock.
pub fn model_outputs(vectors: &[Vector]) -> Vec<(bool, bool, u32, u32)> {
    let mut g = m::PulseGenerator::new();
    vectors
        .iter()
        .map(|v| {
            g.clock(&v.inputs, v.reset);
            pins_of(&g)
        })
        .collect()
}

fn drive(uut: &mut PulseGenerator, v: &Vector) {
    uut.reset.next = v.reset;
    uut.enable.next = v.inputs.enable;
    uut.halt.next = v.inputs.halt;
    uut.rate.next = u64::from(v.inputs.rate as u32).into();
    uut.step_len.next = u64::from(v.inputs.timing.step_len).into();
    uut.step_space.next = u64::from(v.inputs.timing.step_space).into();
    uut.dir_setup.next = u64::from(v.inputs.timing.dir_setup).into();
    uut.dir_hold.next = u64::from(v.inputs.timing.dir_hold).into();
}

/// The rust-hdl axis against the model every clock (phase, position and
/// every step-timer register, and the step, dir, position and status
/// outputs). One case per clock.
pub fn random_rust(clocks: usize, seed: u64) -> CheckReport {
    let mut r = CheckReport::new(
        "pulse_generator",
        &format!(
            "{clocks} random clocks (rates to f/2, reversals, timing changes): rust-hdl vs model"
        ),
        clocks as u64,
    );
    let vectors = stimulus(clocks, seed);
    let mut uut = PulseGenerator::new();
    uut.connect_all();
    let mut g = m::PulseGenerator::new();
    for (k, v) in vectors.iter().enumerate() {
        drive(&mut uut, v);
        settle(&mut uut);
        cycle(&mut uut, |u| &mut u.clock);
        g.clock(&v.inputs, v.reset);
        let got = state_map::generator(uut.probe());
        let want = g;
        let pins = pins_of(&g);
        let got_pins = (
            uut.step.val(),
            uut.dir.val(),
            uut.position.val().index() as u32,
            uut.status.val().index() as u32,
        );
        r.case(
            (got != want)
                .then(|| format!("clock {k} {v:?}: HDL {got:?}, model {want:?}"))
                .or_else(|| {
                    (got_pins != pins).then(|| {
                        format!(
                            "clock {k} {v:?}: (step, dir, position, status) HDL {got_pins:?}, \
                             model {pins:?}"
                        )
                    })
                }),
        );
        if r.failures.len() > 5 {
            break;
        }
    }
    r
}

/// The same stimulus through the generated `pulse_generator.v` in `sim`:
/// `step`, `dir` and `position` after every clock against the model.
pub fn random_verilog(target: impl Into<Target>, clocks: usize, seed: u64) -> CheckReport {
    let target = target.into();
    let mut r = CheckReport::new(
        "pulse_generator",
        &format!("{clocks} random clocks: {} vs model", target.describe()),
        clocks as u64,
    );
    let vectors = stimulus(clocks, seed);
    let want = model_outputs(&vectors);
    let module = catalog::pulse_generator();
    let text = match target.text(&module) {
        Ok(text) => text,
        Err(e) if target.available().is_err() => return r.skip(e),
        Err(e) => {
            r.failures.push(e);
            return r;
        }
    };
    let design = Design {
        top: module.name,
        source: &text,
        inputs: ports_of(&module, &["reset", "enable", "halt", "rate", "move_rate", "moves", "step_len", "step_space", "dir_setup", "dir_hold"]),
        outputs: // `commanded` and `advancing` are combinational (they follow this
        // clock's inputs): connected, compared through `step`, `position`
        // and `pending` instead.
        ports_of(
            &module,
            &["step", "dir", "position", "status", "commanded", "advancing"],
        ),
        clock: Some("clock"),
    };
    let mut rows: Vec<Vec<u64>> = vectors
        .iter()
        .map(|v| {
            let i = &v.inputs;
            vec![
                u64::from(v.reset),
                u64::from(i.enable),
                u64::from(i.halt),
                u64::from(i.rate as u32),
                // Velocity mode: `move_rate` carries a decoy that must
                // not leak through.
                u64::from(!(i.rate as u32)),
                0,
                u64::from(i.timing.step_len),
                u64::from(i.timing.step_space),
                u64::from(i.timing.dir_setup),
                u64::from(i.timing.dir_hold),
            ]
        })
        .collect();
    rows.push(vec![0; 10]);
    match run_vectors(target.sim, &design, &rows) {
        Ok(out) => {
            for (k, &(s, d, p, status)) in want.iter().enumerate() {
                let got = &out[k + 1];
                let want = [u64::from(s), u64::from(d), u64::from(p), u64::from(status)];
                let got = &got[..want.len()];
                r.case((got[..] != want[..]).then(|| {
                    format!(
                        "clock {k} {:?}: Verilog {got:?}, model {want:?}",
                        vectors[k]
                    )
                }));
            }
        }
        Err(e) if target.available().is_err() => return r.skip(e),
        Err(e) => r.failures.push(e),
    }
    r
}

/// Contract of the emitted waveform, checked on the model's outputs (which
/// the HDL equals every clock): with constant timing and no reset, every
/// S1 high run lasts >= step_len clocks, every low run between steps >=
/// step_space, S2 changes only after S1 has been low >= dir_hold clocks and
/// stays >= dir_setup clocks before the next rise, and S2 never changes
/// while S1 is high. Returns violations.
pub fn timing_violations(timing: &StepTiming, out: &[(bool, bool, u32)]) -> Vec<String> {
    let at_least = |x: u32| x.max(1) as usize;
    let mut v = Vec::new();
    let mut last_rise: Option<usize> = None;
    let mut last_fall: Option<usize> = None;
    let mut last_dir_change: Option<usize> = None;
    for k in 1..out.len() {
        let (s0, d0, _) = out[k - 1];
        let (s1, d1, _) = out[k];
        if d1 != d0 {
            if s0 || s1 {
                v.push(format!("clock {k}: S2 changed with S1 high"));
            }
            if let Some(f) = last_fall {
                if k - f < at_least(timing.dir_hold) {
                    v.push(format!(
                        "clock {k}: S2 changed {} clocks after S1 fell",
                        k - f
                    ));
                }
            }
            last_dir_change = Some(k);
        }
        if s1 && !s0 {
            if let Some(f) = last_fall {
                if k - f < at_least(timing.step_space) {
                    v.push(format!("clock {k}: S1 rose {} clocks after it fell", k - f));
                }
            }
            if let Some(c) = last_dir_change {
                if k - c < at_least(timing.dir_setup) {
                    v.push(format!(
                        "clock {k}: S1 rose {} clocks after S2 changed",
                        k - c
                    ));
                }
            }
            last_rise = Some(k);
        }
        if !s1 && s0 {
            if let Some(r) = last_rise {
                if k - r < at_least(timing.step_len) {
                    v.push(format!("clock {k}: S1 high for {} clocks", k - r));
                }
            }
            last_fall = Some(k);
        }
    }
    v
}

/// Runs the model with constant `timing` and `rate` schedule, then idles
/// until the queue drains: the commanded steps (NCO carries, signed) and
/// the emitted waveform.
pub fn run_schedule(
    timing: StepTiming,
    schedule: &[(i32, usize)],
) -> (i64, Vec<(bool, bool, u32)>) {
    let mut g = m::PulseGenerator::new();
    let mut commanded: i64 = 0;
    let mut out = Vec::new();
    let mut step = |g: &mut m::PulseGenerator, inputs: PulseInputs, out: &mut Vec<_>| {
        let (req, _) = g.request(&inputs);
        commanded += match req {
            Request::Up => 1,
            Request::Down => -1,
            Request::None => 0,
        };
        g.clock(&inputs, false);
        let (s, d) = g.outputs();
        out.push((s, d, g.position));
    };
    for &(rate, clocks) in schedule {
        for _ in 0..clocks {
            step(
                &mut g,
                PulseInputs {
                    enable: true,
                    halt: false,
                    rate,
                    timing,
                },
                &mut out,
            );
        }
    }
    let idle = PulseInputs {
        enable: false,
        halt: false,
        rate: 0,
        timing,
    };
    let mut guard = 0;
    while g.busy() {
        step(&mut g, idle, &mut out);
        guard += 1;
        assert!(guard < 10_000_000, "queue does not drain");
    }
    for _ in 0..8 {
        step(&mut g, idle, &mut out);
    }
    (commanded, out)
}

/// The checks `motionhdl verify` shows for the pulse generator; the
/// generated Verilog in Icarus and Verilator only with `external`.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![exhaustive_timer().0, random_rust(200_000, 0x5eed_0001)];
    if external {
        v.push(random_verilog(Simulator::Icarus, 100_000, 0x5eed_0002));
        v.push(random_verilog(Simulator::Verilator, 2_000_000, 0x5eed_0003));
    }
    v
}
