//! Counter bank checks: the rust-hdl bank stepped directly beside the model,
//! every register of every channel compared every clock; and the generated
//! Verilog over long runs of the same stimulus ([`stimulus`]), compared
//! through checksums.

pub mod stimulus;

use crate::harness::{cycle, settle, CheckReport};
use crate::state_map;
use motionhdl_hdl::CounterBank;
use motionhdl_model::counter::{Bank, BusCycle, CounterFeatures, CounterParams};
use motionhdl_model::regmap::{self, Block as RegisterBlock};
use rust_hdl::prelude::*;

/// The rust-hdl bank and the model, stepped together.
pub struct BankPair<const N: usize> {
    pub hdl: CounterBank<N>,
    pub model: Bank,
    pub map: RegisterBlock,
    pub cycles: u64,
    /// The `home` input for the next steps (bit i captures channel i's
    /// count into HOME_COUNT).
    pub home: u32,
    /// The `snapshot_strobe` input for the next steps.
    pub snapshot_strobe: bool,
}

impl<const N: usize> BankPair<N> {
    pub fn new(width: u32, err_bits: u32) -> Self {
        Self::with_params(CounterParams::new(width, err_bits))
    }

    /// Both twins built with `params` (width, error counter, features);
    /// `map` is the full map, whose addresses every build shares.
    pub fn with_params(params: CounterParams) -> Self {
        let mut hdl = CounterBank::<N>::with_params(params);
        hdl.connect_all();
        settle(&mut hdl);
        Self {
            hdl,
            model: Bank::new(N as u32, params),
            map: regmap::counter_bank(N as u32, params.width),
            cycles: 0,
            home: 0,
            snapshot_strobe: false,
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
        self.hdl.home.next = u64::from(self.home).into();
        self.hdl.snapshot_strobe.next = self.snapshot_strobe;
        self.hdl.reset.next = reset;
        self.hdl.addr.next = (bus.addr as u64).into();
        self.hdl.wdata.next = (bus.wdata as u64).into();
        self.hdl.we.next = bus.we;
        self.hdl.re.next = bus.re;
        settle(&mut self.hdl);
        cycle(&mut self.hdl, |h| &mut h.clock);
        self.model
            .clock_strobed(pins, reset, bus, (self.home, self.snapshot_strobe));
        self.cycles += 1;
        self.compare()
    }

    /// Compares read data, the live ERR and SEEN outputs (the safety
    /// block's COUNTER_CAUSE) and every channel's registers with the model.
    pub fn compare(&self) -> Result<(), String> {
        let got = self.hdl.rdata.val().to_u32();
        if got != self.model.rdata() {
            return Err(format!(
                "cycle {}: rdata HDL {got:#x}, model {:#x}",
                self.cycles,
                self.model.rdata()
            ));
        }
        let flags = (
            self.hdl.error.val().index() as u32,
            self.hdl.index_seen.val().index() as u32,
        );
        if flags != self.model.flags() {
            return Err(format!(
                "cycle {}: (error, index_seen) HDL {flags:#x?}, model {:#x?}",
                self.cycles,
                self.model.flags()
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
    long_stimulus_hdl_built(cycles, seed, CounterFeatures::ALL)
}

/// How a build's features read in a check's name: "" for the full build.
pub fn build_label(features: CounterFeatures) -> String {
    let [filter, index, error, snapshot] = CounterFeatures::KEYS;
    let off: Vec<&str> = [
        (features.filter, filter),
        (features.index, index),
        (features.error, error),
        (features.snapshot, snapshot),
    ]
    .into_iter()
    .filter(|(on, _)| !on)
    .map(|(_, key)| key)
    .collect();
    if off.is_empty() {
        String::new()
    } else {
        format!(", built with {} = false", off.join(", "))
    }
}

/// [`long_stimulus_hdl_seeded`] with both twins built with `features`.
pub fn long_stimulus_hdl_built(cycles: u64, seed: u32, features: CounterFeatures) -> CheckReport {
    use stimulus::Stimulus;
    let (axes, width) = (4u32, 28u32);
    let mut r = CheckReport::new(
        "counter_bank",
        &format!(
            "rust-hdl vs model, random encoder/bus stimulus (seed {seed}), 4×28{}, clocks",
            build_label(features)
        ),
        cycles,
    );
    let mut s = Stimulus::new(axes, width, seed);
    let mut p = BankPair::<4>::with_params(
        CounterParams::new(width, regmap::ERR_COUNT_BITS).with_features(features),
    );
    for n in 0..cycles {
        let c = s.clock();
        p.home = c.home;
        p.snapshot_strobe = c.snapshot_strobe;
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
    verilog_long_run_built(target, cycles, CounterFeatures::ALL)
}

/// [`verilog_long_run`] of the bank built with `features`.
pub fn verilog_long_run_built(
    target: impl Into<crate::verilog_sim::Target>,
    cycles: u64,
    features: CounterFeatures,
) -> CheckReport {
    use stimulus::{model_sums, verilog_sums};
    let t = target.into();
    let (axes, width, seed) = (4u32, 28u32, VERILOG_SEED);
    let mut r = CheckReport::new(
        "counter_bank",
        &format!(
            "{} vs model, random stimulus{}, clocks",
            t.describe(),
            build_label(features)
        ),
        cycles,
    );
    if let Err(why) = t.available() {
        return r.skip(why);
    }
    let m = motionhdl_hdl::catalog::counter_bank_with(axes, width, features);
    match t
        .text(&m)
        .and_then(|text| verilog_sums(t.sim, &m, &text, width, seed, cycles))
    {
        Err(e) => r.failures.push(e),
        Ok(got) => {
            let want = model_sums(axes, width, features, seed, cycles);
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

/// The counter bank checks; generated-Verilog runs only when `external`.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![long_stimulus_hdl(20_000)];
    if external {
        v.push(verilog_long_run(
            crate::verilog_sim::Simulator::Icarus,
            30_000,
        ));
        v.push(verilog_long_run(
            crate::verilog_sim::Simulator::Verilator,
            crate::scale::cases("counter_bank_verilator_clocks"),
        ));
    }
    v
}
