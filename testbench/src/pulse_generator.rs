//! Pulse generator checks: the step timer exhaustively at a narrow instance
//! (every reachable state × every request × every timing 0..=2), the whole
//! axis against the model every clock under random rates, reversals and
//! timing changes (rust-hdl, and the generated Verilog in Icarus and
//! Verilator), and contract properties of the emitted waveform.

use crate::harness::{cycle, settle, xorshift, CheckReport};
use crate::state_map;
use crate::tour;
use crate::verilog_sim::{ports_of, run_vectors, Design, Simulator, Target};
use motionhdl_hdl::{catalog, PulseBank, PulseGenerator, StepTimer};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::pulse_generator::{
    self as m, PulseInputs, Request, StepTimer as ModelTimer, StepTimerState, StepTiming,
};
use rust_hdl::prelude::*;

/// The exhaustive instance: a 3-bit queue (±3) and 3-bit timers.
pub const NARROW_P: usize = 3;
pub const NARROW_T: usize = 3;
/// Timing values the exhaustive check applies (each of the four).
pub const NARROW_TIMINGS: u32 = 3;

/// Every (request, timing) input of the exhaustive check.
pub fn narrow_inputs() -> Vec<(Request, StepTiming)> {
    let mut v = Vec::new();
    let n = NARROW_TIMINGS;
    for request in [Request::None, Request::Up, Request::Down] {
        for code in 0..n.pow(4) {
            let d = |k: u32| (code / n.pow(k)) % n;
            v.push((
                request,
                StepTiming {
                    step_len: d(0),
                    step_space: d(1),
                    dir_setup: d(2),
                    dir_hold: d(3),
                },
            ));
        }
    }
    v
}

/// The model's successor; a request the queue refuses becomes none (the
/// NCO would hold).
fn narrow_step(s: &StepTimerState, inp: &(Request, StepTiming)) -> StepTimerState {
    let mut t = ModelTimer::new(NARROW_P as u32, NARROW_T as u32);
    t.set_state(*s);
    let request = if t.accepts(inp.0) {
        inp.0
    } else {
        Request::None
    };
    t.clock(request, &inp.1);
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
            "step timer P={NARROW_P} T={NARROW_T}, every reachable state x request x timing 0..={}: rust-hdl vs model",
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
        let (req, timing) = inputs[i];
        let request = if model.accepts(req) {
            req
        } else {
            Request::None
        };
        uut.request_up.next = request == Request::Up;
        uut.request_down.next = request == Request::Down;
        uut.step_len.next = u64::from(timing.step_len).into();
        uut.step_space.next = u64::from(timing.step_space).into();
        uut.dir_setup.next = u64::from(timing.dir_setup).into();
        uut.dir_hold.next = u64::from(timing.dir_hold).into();
        settle(&mut uut);
        let emit = model.emits(&timing);
        let accept = (model.accepts(Request::Up), model.accepts(Request::Down));
        let got_comb = (
            uut.emit_up.val(),
            uut.emit_down.val(),
            uut.accept_up.val(),
            uut.accept_down.val(),
        );
        let want_comb = (emit > 0, emit < 0, accept.0, accept.1);
        let before = model.state();
        model.clock(request, &timing);
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
                    "from {before:?} with {request:?} {timing:?}: HDL {got:?} {got_comb:?}, model {want:?} {want_comb:?}"
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
    let mut next = xorshift(seed);
    let mut v = vec![
        Vector {
            reset: true,
            inputs: PulseInputs::default()
        };
        4
    ];
    let mut inputs = PulseInputs {
        enable: true,
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
        for k in 0..len {
            v.push(Vector {
                reset: reset && k < 4,
                inputs,
            });
        }
    }
    v.truncate(clocks);
    v
}

/// The model through `vectors`: (S1, S2, position, pending as
/// PENDING_BITS-bit two's complement) after every clock.
pub fn model_outputs(vectors: &[Vector]) -> Vec<(bool, bool, u32, u32)> {
    let mut g = m::PulseGenerator::new();
    let mask = (1u32 << m::PENDING_BITS) - 1;
    vectors
        .iter()
        .map(|v| {
            g.clock(&v.inputs, v.reset);
            let (s, d) = g.outputs();
            (s, d, g.position, g.timer.state().pending as u32 & mask)
        })
        .collect()
}

fn drive(uut: &mut PulseGenerator, v: &Vector) {
    uut.reset.next = v.reset;
    uut.enable.next = v.inputs.enable;
    uut.rate.next = u64::from(v.inputs.rate as u32).into();
    uut.step_len.next = u64::from(v.inputs.timing.step_len).into();
    uut.step_space.next = u64::from(v.inputs.timing.step_space).into();
    uut.dir_setup.next = u64::from(v.inputs.timing.dir_setup).into();
    uut.dir_hold.next = u64::from(v.inputs.timing.dir_hold).into();
}

/// The rust-hdl axis against the model every clock (phase, position and
/// every step-timer register). One case per clock.
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
        let want = (g.phase, g.position, g.timer.state());
        r.case((got != want).then(|| format!("clock {k} {v:?}: HDL {got:?}, model {want:?}")));
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
        inputs: ports_of(&module, &["reset", "enable", "rate", "move_rate", "moves", "step_len", "step_space", "dir_setup", "dir_hold"]),
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
    rows.push(vec![0; 9]);
    match run_vectors(target.sim, &design, &rows) {
        Ok(out) => {
            for (k, &(s, d, p, q)) in want.iter().enumerate() {
                let got = &out[k + 1];
                let busy = q != 0 || s;
                let status = q | u32::from(busy) << 16;
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
                    rate,
                    timing,
                },
                &mut out,
            );
        }
    }
    let idle = PulseInputs {
        enable: false,
        rate: 0,
        timing,
    };
    let mut guard = 0;
    while g.timer.state().pending != 0 || g.outputs().0 {
        step(&mut g, idle, &mut out);
        guard += 1;
        assert!(guard < 10_000_000, "queue does not drain");
    }
    for _ in 0..8 {
        step(&mut g, idle, &mut out);
    }
    (commanded, out)
}

/// One clock of the bank's bus and snapshot strobe.
#[derive(Clone, Copy, Debug)]
pub struct BankVector {
    pub reset: bool,
    pub bus: BusCycle,
    pub snapshot: bool,
}

/// Random register traffic for an `axes`-axis bank: rates (incl. ±f/2 and
/// reversals), timings, modes, RUN masks (several axes at once), SNAPSHOT
/// strobes and reads of every address, including undecoded ones.
pub fn bank_stimulus(axes: u32, width: u32, clocks: usize, seed: u64) -> Vec<BankVector> {
    let map = motionhdl_model::regmap::pulse_bank(axes, width);
    let decoded: Vec<u32> = map.decoded().iter().map(|d| d.0).collect();
    let mut next = xorshift(seed);
    let mut v = vec![
        BankVector {
            reset: true,
            bus: BusCycle::default(),
            snapshot: false
        };
        4
    ];
    while v.len() < clocks {
        let mut bus = BusCycle::default();
        match next() % 16 {
            0 | 1 => {
                let addr = decoded[(next() % decoded.len() as u64) as usize];
                let data = match next() % 4 {
                    0 => next() as u32,
                    1 => (next() as u32) >> (4 + next() % 24),
                    2 => ((next() % 8) as u32) | (((next() % 8) as u32) << 16),
                    _ => (next() as i32 >> (4 + next() % 24)) as u32,
                };
                bus = BusCycle::write(addr, data);
            }
            2 | 3 => {
                let addr = if next().is_multiple_of(8) {
                    (next() % 512) as u32
                } else {
                    decoded[(next() % decoded.len() as u64) as usize]
                };
                bus = BusCycle::read(addr);
            }
            _ => {}
        }
        v.push(BankVector {
            reset: next().is_multiple_of(5000),
            bus,
            snapshot: next().is_multiple_of(64),
        });
    }
    v.truncate(clocks);
    v
}

/// The rust-hdl bank (4 axes) against the model every clock: `rdata`, F1/F2
/// of every axis and every generator's registers. One case per clock.
pub fn bank_rust(clocks: usize, seed: u64) -> CheckReport {
    const N: usize = 4;
    let width = 28;
    let mut r = CheckReport::new(
        "pulse_generator",
        &format!(
            "pulse bank {N} axes, {clocks} clocks of random register traffic: rust-hdl vs model"
        ),
        clocks as u64,
    );
    let vectors = bank_stimulus(N as u32, width, clocks, seed);
    let mut uut = PulseBank::<N>::new(width);
    uut.connect_all();
    let mut model = m::PulseBank::new(N as u32, width);
    for (k, v) in vectors.iter().enumerate() {
        uut.reset.next = v.reset;
        uut.addr.next = u64::from(v.bus.addr).into();
        uut.wdata.next = u64::from(v.bus.wdata).into();
        uut.we.next = v.bus.we;
        uut.re.next = v.bus.re;
        uut.snapshot.next = v.snapshot;
        settle(&mut uut);
        cycle(&mut uut, |u| &mut u.clock);
        model.clock(v.reset, &v.bus, v.snapshot);
        let got_rdata = uut.rdata.val().index() as u32;
        let mut bad = (got_rdata != model.rdata())
            .then(|| format!("rdata HDL {got_rdata:#x}, model {:#x}", model.rdata()));
        for i in 0..N {
            let f = (uut.f1.val().get_bit(i), uut.f2.val().get_bit(i));
            let g = state_map::generator(uut.generator(i).probe());
            let mg = model.generator(i);
            let want_g = (mg.phase, mg.position, mg.timer.state());
            let e = uut.engine(i).probe();
            let want_e = model.engine(i).probe();
            if e != want_e {
                bad.get_or_insert(format!("axis {i}: engine HDL {e:?}, model {want_e:?}"));
            }
            if f != model.outputs(i) || g != want_g {
                bad.get_or_insert(format!(
                    "axis {i}: F HDL {f:?} model {:?}; HDL {g:?}, model {want_g:?}",
                    model.outputs(i)
                ));
            }
        }
        r.case(bad.map(|b| format!("clock {k} {v:?}: {b}")));
        if r.failures.len() > 5 {
            break;
        }
    }
    r
}

/// Output modes of a pulse bank axis, as CTRL values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    PulseDir,
    CwCcw,
    Quadrature,
}

impl Output {
    pub const ALL: [Output; 3] = [Output::PulseDir, Output::CwCcw, Output::Quadrature];
    /// PULSE.AX[n].CTRL for this output.
    pub fn ctrl(self) -> u32 {
        match self {
            Output::PulseDir => 0,
            Output::CwCcw => 1,
            Output::Quadrature => 2,
        }
    }
    /// The counter bank mode that counts it one for one.
    pub fn counter_mode(self) -> u32 {
        use motionhdl_model::regmap::mode;
        match self {
            Output::PulseDir => mode::PULSE_DIR,
            Output::CwCcw => mode::CW_CCW,
            Output::Quadrature => mode::X4,
        }
    }
}

/// The dual-CPU seed's closed loop in rust-hdl: pulse bank axis 0 → its
/// registered selector or quadrature output → counter bank channel 0
/// (A = F1, B = F2) in the matching counting mode. Random rate schedule with
/// reversals and random timings; after the queue drains, a SNAPSHOT, and
/// COUNT read over the counter's bus must equal the generator's position.
/// Returns (emitted position, counted, clocks).
pub fn loopback(output: Output, seed: u64, segments: usize) -> (i64, i64, u64) {
    use motionhdl_hdl::CounterBank;
    use motionhdl_model::regmap;
    const W: u32 = 28;
    let pmap = regmap::pulse_bank(1, W);
    let cmap = regmap::counter_bank(1, W);
    let pax = pmap.array("AX");
    let cch = cmap.array("CH");
    let mut pb = PulseBank::<1>::new(W);
    let mut cb = CounterBank::<1>::new(W);
    pb.connect_all();
    cb.connect_all();
    let mut clocks = 0u64;
    let mut step = |pb: &mut PulseBank<1>,
                    cb: &mut CounterBank<1>,
                    pbus: BusCycle,
                    cbus: BusCycle,
                    reset: bool| {
        pb.reset.next = reset;
        cb.reset.next = reset;
        pb.addr.next = u64::from(pbus.addr).into();
        pb.wdata.next = u64::from(pbus.wdata).into();
        pb.we.next = pbus.we;
        pb.re.next = pbus.re;
        pb.snapshot.next = false;
        cb.addr.next = u64::from(cbus.addr).into();
        cb.wdata.next = u64::from(cbus.wdata).into();
        cb.we.next = cbus.we;
        cb.re.next = cbus.re;
        settle(pb);
        cb.a.next = u64::from(pb.f1.val().get_bit(0)).into();
        cb.b.next = u64::from(pb.f2.val().get_bit(0)).into();
        cb.z.next = 0.into();
        settle(cb);
        cycle(pb, |u| &mut u.clock);
        cycle(cb, |u| &mut u.clock);
        clocks += 1;
    };
    let idle = BusCycle::default();
    for _ in 0..6 {
        step(&mut pb, &mut cb, idle, idle, true);
    }
    let counter_mode = output.counter_mode();
    step(
        &mut pb,
        &mut cb,
        idle,
        BusCycle::write(cch.address(0, "CTRL"), counter_mode),
        false,
    );
    step(
        &mut pb,
        &mut cb,
        BusCycle::write(pax.address(0, "CTRL"), output.ctrl()),
        idle,
        false,
    );
    let mut next = xorshift(seed);
    let t = |n: u64| (n % 5) as u32;
    let timing = t(next()) | t(next()) << 16;
    step(
        &mut pb,
        &mut cb,
        BusCycle::write(pax.address(0, "STEP_TIMING"), timing),
        idle,
        false,
    );
    let timing = t(next()) | t(next()) << 16;
    step(
        &mut pb,
        &mut cb,
        BusCycle::write(pax.address(0, "DIR_TIMING"), timing),
        idle,
        false,
    );
    step(
        &mut pb,
        &mut cb,
        BusCycle::write(pmap.register("RUN").offset, 1),
        idle,
        false,
    );
    for _ in 0..segments {
        let rate = match next() % 4 {
            0 => i32::MIN,
            1 => i32::MAX,
            _ => (next() as i32) >> (next() % 12),
        };
        step(
            &mut pb,
            &mut cb,
            BusCycle::write(pax.address(0, "RATE"), rate as u32),
            idle,
            false,
        );
        for _ in 0..(next() % 500) {
            step(&mut pb, &mut cb, idle, idle, false);
        }
    }
    step(
        &mut pb,
        &mut cb,
        BusCycle::write(pmap.register("RUN").offset, 0),
        idle,
        false,
    );
    let mut guard = 0;
    while pb.generator(0).probe().2.pending != 0 || pb.generator(0).step.val() {
        step(&mut pb, &mut cb, idle, idle, false);
        guard += 1;
        assert!(guard < 1_000_000, "queue does not drain");
    }
    // Selector, synchronisers and decoder: a few clocks to settle.
    for _ in 0..10 {
        step(&mut pb, &mut cb, idle, idle, false);
    }
    step(
        &mut pb,
        &mut cb,
        idle,
        BusCycle::write(cmap.register("SNAPSHOT").offset, 0),
        false,
    );
    step(
        &mut pb,
        &mut cb,
        idle,
        BusCycle::read(cch.address(0, "COUNT")),
        false,
    );
    step(&mut pb, &mut cb, idle, idle, false);
    let counted = cb.rdata.val().index() as u32 as i32 as i64;
    let position =
        motionhdl_model::counter::sign_extend(pb.generator(0).probe().1, W) as i32 as i64;
    (position, counted, clocks)
}

/// A position move in rust-hdl beside the model, every clock: an axis of a
/// 2-axis bank in MOVES mode gets `segments` pushed (more than the FIFO
/// holds, topped up as it drains, as firmware streams an S-curve), runs
/// until STATUS shows DONE and not BUSY, and the position must be the sum
/// of the segments' steps (signed by their rates). Returns the report, the
/// final position and the expected one.
pub fn move_rust(segments: &[m::Segment], timing: StepTiming) -> (CheckReport, i64, i64) {
    const N: usize = 2;
    const W: u32 = 32;
    let map = motionhdl_model::regmap::pulse_bank(N as u32, W);
    let ax = map.array("AX");
    let status = ax.register("STATUS");
    let mut r = CheckReport::new(
        "pulse_generator",
        "position move through the segment FIFO",
        0,
    );
    let mut uut = PulseBank::<N>::new(W);
    uut.connect_all();
    let mut model = m::PulseBank::new(N as u32, W);
    let mut clocks = 0u64;
    let mut step =
        |uut: &mut PulseBank<N>, model: &mut m::PulseBank, bus: BusCycle, r: &mut CheckReport| {
            uut.reset.next = clocks < 4;
            uut.addr.next = u64::from(bus.addr).into();
            uut.wdata.next = u64::from(bus.wdata).into();
            uut.we.next = bus.we;
            uut.re.next = bus.re;
            uut.snapshot.next = false;
            settle(uut);
            cycle(uut, |u| &mut u.clock);
            model.clock(clocks < 4, &bus, false);
            clocks += 1;
            let a = 1;
            let got = (
                uut.engine(a).probe(),
                state_map::generator(uut.generator(a).probe()),
            );
            let g = model.generator(a);
            let want = (
                model.engine(a).probe(),
                (g.phase, g.position, g.timer.state()),
            );
            r.case((got != want).then(|| format!("clock {clocks}: HDL {got:?}, model {want:?}")));
        };
    let idle = BusCycle::default();
    for _ in 0..4 {
        step(&mut uut, &mut model, idle, &mut r);
    }
    let w = |name: &str, v: u32| BusCycle::write(ax.address(1, name), v);
    step(&mut uut, &mut model, w("CTRL", 0b100), &mut r);
    step(
        &mut uut,
        &mut model,
        w("STEP_TIMING", timing.step_len | timing.step_space << 16),
        &mut r,
    );
    step(
        &mut uut,
        &mut model,
        w("DIR_TIMING", timing.dir_setup | timing.dir_hold << 16),
        &mut r,
    );
    step(
        &mut uut,
        &mut model,
        BusCycle::write(map.register("RUN").offset, 0b10),
        &mut r,
    );
    let mut next = 0;
    let mut guard = 0u64;
    loop {
        let s = model.read_value(ax.address(1, "STATUS"));
        let level = status.field("FIFO_LEVEL").get(s) as usize;
        if next < segments.len() && level < m::SEGMENT_FIFO_DEPTH {
            let seg = segments[next];
            step(&mut uut, &mut model, w("SEG_STEPS", seg.steps), &mut r);
            step(&mut uut, &mut model, w("SEG_RATE", seg.rate as u32), &mut r);
            step(
                &mut uut,
                &mut model,
                w("SEG_ACCEL", seg.accel as u32),
                &mut r,
            );
            step(&mut uut, &mut model, w("SEG_PUSH", 0), &mut r);
            next += 1;
            continue;
        }
        if next == segments.len()
            && status.field("DONE").get(s) == 1
            && status.field("BUSY").get(s) == 0
        {
            break;
        }
        step(&mut uut, &mut model, idle, &mut r);
        guard += 1;
        if guard > 5_000_000 {
            r.failures.push("the move does not finish".into());
            break;
        }
        if r.failures.len() > 5 {
            break;
        }
    }
    assert_eq!(
        model.read_value(ax.address(1, "STATUS")) & status.field("OVERFLOW").mask(),
        0,
        "the stream never overfills the FIFO"
    );
    let position = model.generator(1).position as i32 as i64;
    let expected: i64 = segments
        .iter()
        .map(|s| i64::from(s.steps) * if s.rate < 0 { -1 } else { 1 })
        .sum();
    r.expected = r.covered;
    (r, position, expected)
}

/// The checks `motionhdl verify` shows for the pulse generator; the
/// generated Verilog in Icarus and Verilator only with `external`.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![
        exhaustive_timer().0,
        random_rust(200_000, 0x5eed_0001),
        bank_rust(100_000, 0x5eed_0004),
    ];
    if external {
        v.push(random_verilog(Simulator::Icarus, 100_000, 0x5eed_0002));
        v.push(random_verilog(Simulator::Verilator, 2_000_000, 0x5eed_0003));
    }
    v
}
