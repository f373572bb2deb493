//! Counter bank checks: the rust-hdl bank stepped directly beside the model,
//! every register of every channel compared every clock.

use crate::harness::{cycle, settle, CheckReport};
use crate::state_map;
use crate::tour::{explore, tour};
use motionhdl_hdl::{CounterBank, InputFilter as HdlFilter};
use motionhdl_model::counter::{
    Bank, BusCycle, Channel, ChannelInputs, ChannelState, CounterParams, InputFilter,
};
use motionhdl_model::regmap::{self, Block as RegisterBlock};
use rust_hdl::prelude::*;
use std::collections::BTreeSet;

/// The rust-hdl bank and the model, stepped together.
pub struct BankPair<const N: usize> {
    pub hdl: CounterBank<N>,
    pub model: Bank,
    pub map: RegisterBlock,
    pub cycles: u64,
}

impl<const N: usize> BankPair<N> {
    pub fn new(width: u32, err_bits: u32) -> Self {
        let mut hdl = CounterBank::<N>::with_err_bits(width, err_bits);
        hdl.connect_all();
        settle(&mut hdl);
        Self {
            hdl,
            model: Bank::new(N as u32, CounterParams::new(width, err_bits)),
            map: regmap::counter_bank(N as u32, width),
            cycles: 0,
        }
    }

    /// One clock with the given pins (a, b, z per channel), reset and bus
    /// cycle; then compares read data and every channel register.
    pub fn step(
        &mut self,
        pins: &[(bool, bool, bool)],
        reset: bool,
        bus: &BusCycle,
    ) -> Result<(), String> {
        assert_eq!(pins.len(), N);
        let word = |f: fn(&(bool, bool, bool)) -> bool| -> Bits<N> {
            let mut w = 0u64;
            for (i, p) in pins.iter().enumerate() {
                if f(p) {
                    w |= 1 << i;
                }
            }
            w.into()
        };
        self.hdl.a.next = word(|p| p.0);
        self.hdl.b.next = word(|p| p.1);
        self.hdl.z.next = word(|p| p.2);
        self.hdl.reset.next = reset;
        self.hdl.addr.next = (bus.addr as u64).into();
        self.hdl.wdata.next = (bus.wdata as u64).into();
        self.hdl.we.next = bus.we;
        self.hdl.re.next = bus.re;
        settle(&mut self.hdl);
        cycle(&mut self.hdl, |h| &mut h.clock);
        self.model.clock(pins, reset, bus);
        self.cycles += 1;
        self.compare()
    }

    /// Compares read data and every channel's registers with the model.
    pub fn compare(&self) -> Result<(), String> {
        let got = self.hdl.rdata.val().to_u32();
        if got != self.model.rdata() {
            return Err(format!(
                "cycle {}: rdata HDL {got:#x}, model {:#x}",
                self.cycles,
                self.model.rdata()
            ));
        }
        for i in 0..N {
            let h = state_map::channel(self.hdl.channel(i).probe());
            let m = *self.model.channel(i).state();
            if h != m {
                return Err(format!(
                    "cycle {}: channel {i} differs\n HDL   {h:?}\n model {m:?}",
                    self.cycles
                ));
            }
            if !self.hdl.channel(i).flags_consistent() {
                return Err(format!(
                    "cycle {}: channel {i}: a derived flag (counter look-ahead, filter count, error saturation) does not match what it summarises",
                    self.cycles
                ));
            }
        }
        Ok(())
    }

    /// A bus write of `data` to word address `addr`, with pins held.
    pub fn write(
        &mut self,
        pins: &[(bool, bool, bool)],
        addr: u32,
        data: u32,
    ) -> Result<(), String> {
        self.step(pins, false, &BusCycle::write(addr, data))
    }

    /// A bus read of `addr`: returns the data, checked against the model.
    pub fn read(&mut self, pins: &[(bool, bool, bool)], addr: u32) -> Result<u32, String> {
        self.step(pins, false, &BusCycle::read(addr))?;
        self.step(pins, false, &BusCycle::default())?;
        Ok(self.hdl.rdata.val().to_u32())
    }

    /// Holds reset for `n` clocks.
    pub fn reset(&mut self, pins: &[(bool, bool, bool)], n: usize) -> Result<(), String> {
        for _ in 0..n {
            self.step(pins, true, &BusCycle::default())?;
        }
        Ok(())
    }
}

/// Every reachable (state, input) pair of the input filter, for every
/// setting F in 0..=15, rust-hdl vs model every clock.
pub fn filter_exhaustive() -> CheckReport {
    let inputs: Vec<(bool, bool)> =
        vec![(false, false), (true, false), (false, true), (true, true)];
    let mut total_expected = 0;
    let mut covered = 0;
    let mut failures = Vec::new();
    for setting in 0u8..16 {
        let step = |s: &InputFilter, &(pin, reset): &(bool, bool)| {
            let mut n = *s;
            n.clock(pin, setting, reset);
            n
        };
        let g = explore(InputFilter::default(), &inputs, step, 1 << 16).expect("small state space");
        total_expected += g.pairs() as u64;
        let mut hdl = HdlFilter::default();
        hdl.connect_all();
        hdl.setting.next = (setting as u64).into();
        settle(&mut hdl);
        let mut model = InputFilter::default();
        let mut pairs = BTreeSet::new();
        for (n, inp) in tour(&g).into_iter().enumerate() {
            let (pin, reset) = inputs[inp];
            pairs.insert((model, inp));
            hdl.pin.next = pin;
            hdl.reset.next = reset;
            settle(&mut hdl);
            cycle(&mut hdl, |h| &mut h.clock);
            model.clock(pin, setting, reset);
            if state_map::filter(hdl.probe()) != model {
                failures.push(format!(
                    "F={setting} step {n} pin={pin} reset={reset}: HDL {:?}, model {model:?}",
                    state_map::filter(hdl.probe())
                ));
                break;
            }
        }
        covered += pairs.len() as u64;
    }
    let mut r = CheckReport::new(
        "counter_bank",
        "input filter, every reachable state × input, F=0..15",
        total_expected,
    );
    r.covered = covered;
    r.failures = failures;
    r
}

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
pub fn core_exhaustive(
    label: &str,
    width: u32,
    err_bits: u32,
    ctrl: u32,
    cmds: &[u32],
) -> CheckReport {
    let map = regmap::counter_bank(1, width);
    let ch = map.array("CH");
    let params = CounterParams::new(width, err_bits);
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
    let mut pair = BankPair::<1>::new(width, err_bits);
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
    let jobs = core_check_jobs();
    std::thread::scope(|scope| {
        let handles: Vec<_> = jobs.into_iter().map(|job| scope.spawn(job)).collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("core check panicked"))
            .collect()
    })
}

type Job = Box<dyn FnOnce() -> CheckReport + Send>;

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
                w,
                2,
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
            w,
            2,
            ctrl,
            &cmds[..2],
        )
    }));
    let w = 3;
    let cmds = [0, cmd(w, "CLEAR_STATUS"), cmd(w, "ARM"), cmd(w, "CLEAR")];
    let ctrl = ctrl_value(
        w,
        &[
            ("MODE", regmap::mode::X4),
            ("ERR_EN", 1),
            ("IDX_LATCH", 1),
            ("IDX_CLEAR", 1),
            ("IDX_GATE", 1),
            ("IDX_ONESHOT", 1),
            ("IDX_INVERT", 1),
        ],
    );
    out.push(Box::new(move || {
        core_exhaustive(
            "channel core X4 + every index feature, W=3, every reachable state × input",
            w,
            2,
            ctrl,
            &cmds,
        )
    }));
    out
}

/// The long deterministic stimulus through the rust-hdl bank beside the
/// model, every register compared every clock.
pub fn long_stimulus_hdl(cycles: u64) -> CheckReport {
    long_stimulus_hdl_seeded(cycles, 12345)
}

/// Seed of the generated-Verilog runs' stimulus ([`verilog_long_run`]).
pub const VERILOG_SEED: u32 = 777;

/// [`long_stimulus_hdl`] with another seed: with [`VERILOG_SEED`], the
/// stimulus of the generated-Verilog runs, clock for clock.
pub fn long_stimulus_hdl_seeded(cycles: u64, seed: u32) -> CheckReport {
    use crate::counter_stimulus::Stimulus;
    let (axes, width) = (4u32, 28u32);
    let mut r = CheckReport::new(
        "counter_bank",
        &format!("rust-hdl vs model, random encoder/bus stimulus (seed {seed}), 4×28, clocks"),
        cycles,
    );
    let mut s = Stimulus::new(axes, width, seed);
    let mut p = BankPair::<4>::new(width, regmap::ERR_COUNT_BITS);
    for n in 0..cycles {
        let c = s.clock();
        if let Err(e) = p.step(&c.pins, c.reset, &c.bus) {
            r.failures.push(format!("clock {n}: {e}"));
            break;
        }
        r.covered += 1;
    }
    r
}

/// The generated `counter_bank.v` (4×28), or its netlist, over `cycles`
/// clocks of the long stimulus, compared with the model through checksums
/// of the stimulus and of every clock's read data.
pub fn verilog_long_run(target: impl Into<crate::verilog_sim::Target>, cycles: u64) -> CheckReport {
    use crate::counter_stimulus::{model_sums, verilog_sums};
    let t = target.into();
    let (axes, width, seed) = (4u32, 28u32, VERILOG_SEED);
    let mut r = CheckReport::new(
        "counter_bank",
        &format!("{} vs model, random stimulus, clocks", t.describe()),
        cycles,
    );
    if let Err(why) = t.available() {
        return r.skip(why);
    }
    let m = motionhdl_hdl::catalog::counter_bank(axes, width);
    match t
        .text(&m)
        .and_then(|text| verilog_sums(t.sim, &m, &text, width, seed, cycles))
    {
        Err(e) => r.failures.push(e),
        Ok(got) => {
            let want = model_sums(axes, width, seed, cycles);
            if got.stimulus != want.stimulus {
                r.failures
                    .push("the Verilog and Rust stimulus generators differ".into());
            } else if got.rdata != want.rdata {
                r.failures.push(format!(
                    "read data checksum {:#x}, model {:#x}",
                    got.rdata, want.rdata
                ));
            } else {
                r.covered = cycles;
            }
        }
    }
    r
}

/// Every counter bank check; generated-Verilog runs only when `external`.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![filter_exhaustive()];
    v.extend(core_checks());
    v.push(long_stimulus_hdl(20_000));
    if external {
        v.push(verilog_long_run(
            crate::verilog_sim::Simulator::Icarus,
            30_000,
        ));
        v.push(verilog_long_run(
            crate::verilog_sim::Simulator::Verilator,
            10_000_000,
        ));
    }
    v
}
