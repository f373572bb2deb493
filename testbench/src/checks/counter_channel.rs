//! Counter channel checks: the decoder, counter and index logic of one
//! channel through every reachable (state, input) pair in each mode,
//! rust-hdl beside the model every clock.

use super::counter_bank::{build_label, BankPair};
use crate::harness::CheckReport;
use crate::tour::{explore, tour};
use motionhdl_model::counter::{
    BusCycle, Channel, ChannelInputs, ChannelState, CounterFeatures, CounterParams, InputFilter,
};
use motionhdl_model::regmap::{self};
use std::collections::BTreeSet;

/// The part of a channel's state the decoder, counter and index logic own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Core {
    pub a_prev: bool,
    pub b_prev: bool,
    pub zg_prev: bool,
    pub zg_q: bool,
    pub err_q: bool,
    pub up_q: bool,
    pub down_q: bool,
    pub load_q: bool,
    pub index_latch_q: bool,
    pub index_clear_q: bool,
    pub count: u32,
    pub index: u32,
    pub err: bool,
    pub err_count: u32,
    pub seen: bool,
    pub armed: bool,
}

impl Core {
    pub fn of(s: &ChannelState) -> Self {
        Self {
            a_prev: s.a_prev,
            b_prev: s.b_prev,
            zg_prev: s.zg_prev,
            zg_q: s.zg_q,
            err_q: s.err_q,
            up_q: s.up_q,
            down_q: s.down_q,
            load_q: s.load_q,
            index_latch_q: s.index_latch_q,
            index_clear_q: s.index_clear_q,
            count: s.count,
            index: s.index,
            err: s.err,
            err_count: s.err_count,
            seen: s.seen,
            armed: s.armed,
        }
    }
}

/// Input of the core: accepted levels (a, b, z) and a CMD write (0 = none).
pub type CoreInput = (bool, bool, bool, u32);

/// Exhaustive check of one channel's decoder, counter, index and error logic
/// at a narrow instance: every reachable (core state, input) pair under a
/// fixed CTRL, driven through the full rust-hdl bank's pins (filters off, so
/// the synchroniser and filter are a 3-clock delay) and compared with the
/// model every clock. Coverage is counted from the model's observed state.
pub fn core_exhaustive(label: &str, params: CounterParams, ctrl: u32, cmds: &[u32]) -> CheckReport {
    let width = params.width;
    let map = regmap::counter_bank(1, width);
    let ch = map.array("CH");
    // The model channel after CTRL is written, idle pins.
    let mut setup = Channel::new(params);
    for _ in 0..3 {
        setup.clock(&ChannelInputs {
            reset: true,
            ..Default::default()
        });
    }
    setup.clock(&ChannelInputs {
        ctrl_write: Some(ctrl),
        ..Default::default()
    });
    for _ in 0..4 {
        setup.clock(&ChannelInputs::default());
    }
    let base = *setup.state();
    let mut inputs: Vec<CoreInput> = Vec::new();
    for &cmd in cmds {
        for l in 0..8u8 {
            inputs.push((l & 1 != 0, l & 2 != 0, l & 4 != 0, cmd));
        }
    }
    let step = |c: &Core, &(a, b, z, cmd): &CoreInput| -> Core {
        let mut s = base;
        for (f, level) in [(&mut s.fa, a), (&mut s.fb, b), (&mut s.fz, z)] {
            *f = InputFilter {
                s1: level,
                s2: level,
                level,
                cnt: 0,
            };
        }
        s.a_prev = c.a_prev;
        s.b_prev = c.b_prev;
        s.zg_prev = c.zg_prev;
        s.zg_q = c.zg_q;
        s.err_q = c.err_q;
        s.up_q = c.up_q;
        s.down_q = c.down_q;
        s.load_q = c.load_q;
        s.index_latch_q = c.index_latch_q;
        s.index_clear_q = c.index_clear_q;
        s.count = c.count;
        s.index = c.index;
        s.err = c.err;
        s.err_count = c.err_count;
        s.seen = c.seen;
        s.armed = c.armed;
        let mut m = Channel::new(params);
        m.set_state(s);
        m.clock(&ChannelInputs {
            a,
            b,
            z,
            cmd_write: (cmd != 0).then_some(cmd),
            ..Default::default()
        });
        Core::of(m.state())
    };
    let g = match explore(Core::of(&base), &inputs, step, 1 << 20) {
        Ok(g) => g,
        Err(e) => {
            let mut r = CheckReport::new("counter_bank", label, 0);
            r.failures.push(e);
            return r;
        }
    };
    let mut r = CheckReport::new("counter_bank", label, g.pairs() as u64);
    let t = tour(&g);

    // Drive the bank: the same setup, then pins 3 clocks ahead of the core.
    const LEAD: usize = 3;
    let mut pair = BankPair::<1>::with_params(params);
    let idle = [(false, false, false)];
    let cmd_addr = ch.address(0, "CMD");
    let run = (|| -> Result<BTreeSet<(Core, usize)>, String> {
        pair.reset(&idle, 3)?;
        pair.write(&idle, ch.address(0, "CTRL"), ctrl)?;
        for _ in 0..LEAD + 1 {
            pair.step(&idle, false, &BusCycle::default())?;
        }
        if Core::of(pair.model.channel(0).state()) != Core::of(&base) {
            return Err("setup did not reach the tour's start state".into());
        }
        let mut covered = BTreeSet::new();
        let input_index = |inp: &CoreInput| inputs.iter().position(|x| x == inp).unwrap();
        for k in 0..t.len() + LEAD {
            let pins = match t.get(k) {
                Some(&i) => [(inputs[i].0, inputs[i].1, inputs[i].2)],
                None => idle,
            };
            let cmd = if k >= LEAD { inputs[t[k - LEAD]].3 } else { 0 };
            // Observe the pair this clock applies: pre-edge core and levels.
            let s = pair.model.channel(0).state();
            let observed = (s.fa.level, s.fb.level, s.fz.level, cmd);
            if k >= LEAD {
                covered.insert((Core::of(s), input_index(&observed)));
            }
            let bus = if cmd != 0 {
                BusCycle::write(cmd_addr, cmd)
            } else {
                BusCycle::default()
            };
            pair.step(&pins, false, &bus)?;
        }
        Ok(covered)
    })();
    match run {
        Ok(covered) => {
            let states: BTreeSet<Core> = g.states.iter().copied().collect();
            r.covered = covered.iter().filter(|(c, _)| states.contains(c)).count() as u64;
        }
        Err(e) => r.failures.push(e),
    }
    r
}

/// The CTRL value with the given fields set, from the register map.
pub fn ctrl_value(width: u32, fields: &[(&str, u32)]) -> u32 {
    let map = regmap::counter_bank(1, width);
    let ctrl = map.array("CH").register("CTRL");
    fields.iter().fold(0, |v, (name, x)| {
        let f = ctrl.field(name);
        assert!(*x < (1 << f.width), "{name} = {x} does not fit");
        v | (x << f.lsb)
    })
}

/// The exhaustive core checks `motionhdl verify` runs: each mode at W=4
/// with a 2-bit error counter, error latching and one-shot arming on; then
/// X4 reversed; then every index feature at once at W=3 (the index latch
/// multiplies the state space by 2^W).
pub fn core_checks() -> Vec<CheckReport> {
    run_jobs(core_check_jobs())
}

/// Runs the tours side by side, one thread each.
fn run_jobs(jobs: Vec<Job>) -> Vec<CheckReport> {
    std::thread::scope(|scope| {
        let handles: Vec<_> = jobs.into_iter().map(|job| scope.spawn(job)).collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("core check panicked"))
            .collect()
    })
}

type Job = Box<dyn FnOnce() -> CheckReport + Send>;

/// CTRL of the index tours: X4, error latching and every index feature.
const EVERY_INDEX_FEATURE: [(&str, u32); 7] = [
    ("MODE", regmap::mode::X4),
    ("ERR_EN", 1),
    ("IDX_LATCH", 1),
    ("IDX_CLEAR", 1),
    ("IDX_GATE", 1),
    ("IDX_ONESHOT", 1),
    ("IDX_INVERT", 1),
];

fn core_check_jobs() -> Vec<Job> {
    let cmd = |w: u32, name: &str| {
        regmap::counter_bank(1, w)
            .array("CH")
            .register("CMD")
            .field(name)
            .mask()
    };
    let mut out = Vec::new();
    let w = 4;
    let cmds = [0, cmd(w, "CLEAR_STATUS"), cmd(w, "ARM")];
    for (name, mode) in [
        ("X4", regmap::mode::X4),
        ("X2", regmap::mode::X2),
        ("X1", regmap::mode::X1),
        ("PULSE_DIR", regmap::mode::PULSE_DIR),
        ("CW_CCW", regmap::mode::CW_CCW),
    ] {
        let ctrl = ctrl_value(w, &[("MODE", mode), ("ERR_EN", 1), ("IDX_ONESHOT", 1)]);
        out.push(Box::new(move || {
            core_exhaustive(
                &format!("channel core {name}, W=4, every reachable state × input"),
                CounterParams::new(w, 2),
                ctrl,
                &cmds,
            )
        }) as Job);
    }
    // Without IDX_ONESHOT nothing disarms, so no ARM here: armed stays 0.
    let ctrl = ctrl_value(
        w,
        &[("MODE", regmap::mode::X4), ("REVERSE", 1), ("ERR_EN", 1)],
    );
    out.push(Box::new(move || {
        core_exhaustive(
            "channel core X4 reversed, W=4, every reachable state × input",
            CounterParams::new(w, 2),
            ctrl,
            &cmds[..2],
        )
    }));
    let w = 3;
    let cmds = [0, cmd(w, "CLEAR_STATUS"), cmd(w, "ARM"), cmd(w, "CLEAR")];
    let ctrl = ctrl_value(w, &EVERY_INDEX_FEATURE);
    out.push(Box::new(move || {
        core_exhaustive(
            "channel core X4 + every index feature, W=3, every reachable state × input",
            CounterParams::new(w, 2),
            ctrl,
            &cmds,
        )
    }));
    out
}

/// The exhaustive core checks of builds that leave features out, each with
/// the same CTRL and commands as a full-build tour, the absent fields' bits
/// included (so the tour shows them ignored): without the index at W=4
/// (error latching on), without error detection at W=3 (every index feature
/// on), and with index, error and filter all out at W=4. A build without the
/// filter or the snapshot changes nothing the core sees (the filter's tour
/// and the bank's random runs check those).
pub fn core_checks_of_partial_builds() -> Vec<CheckReport> {
    run_jobs(partial_build_jobs())
}

fn partial_build_jobs() -> Vec<Job> {
    let full = CounterFeatures::ALL;
    let builds = [
        (
            4,
            CounterFeatures {
                index: false,
                ..full
            },
        ),
        (
            3,
            CounterFeatures {
                error: false,
                ..full
            },
        ),
        (
            4,
            CounterFeatures {
                filter: false,
                index: false,
                error: false,
                ..full
            },
        ),
    ];
    builds
        .into_iter()
        .map(|(w, features)| {
            let cmd = |name: &str| {
                regmap::counter_bank(1, w)
                    .array("CH")
                    .register("CMD")
                    .field(name)
                    .mask()
            };
            let cmds = [0, cmd("CLEAR_STATUS"), cmd("ARM"), cmd("CLEAR")];
            let ctrl = ctrl_value(w, &EVERY_INDEX_FEATURE);
            Box::new(move || {
                core_exhaustive(
                    &format!(
                        "channel core X4, every CTRL feature written, W={w}{}, every reachable state × input",
                        build_label(features)
                    ),
                    CounterParams::new(w, 2).with_features(features),
                    ctrl,
                    &cmds,
                )
            }) as Job
        })
        .collect()
}

/// The channel core checks `motionhdl verify` runs.
pub fn all(_external: bool) -> Vec<CheckReport> {
    let mut v = core_checks();
    v.extend(core_checks_of_partial_builds());
    v
}
