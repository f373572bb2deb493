//! Pulse bank checks: the bank of axes against the model every clock under
//! random register traffic, the closed loop of an axis into the counter
//! bank in every output mode, and a position move streamed through the
//! segment FIFO. The single axis and its step timer are
//! `pulse_generator.rs`.

pub mod braking;

use crate::harness::{cycle, settle, CheckReport, Rng};
use crate::state_map;
use motionhdl_hdl::PulseBank;
use motionhdl_model::counter::BusCycle;
use motionhdl_model::pulse_generator::{self as m, StepTiming};
use rust_hdl::prelude::*;

/// One clock of the bank's bus and snapshot strobe.
#[derive(Clone, Copy, Debug)]
pub struct BankVector {
    pub reset: bool,
    /// The safety block's HALT and per-direction stops.
    pub stops: m::Stops,
    pub bus: BusCycle,
    pub snapshot: bool,
}

/// Random register traffic for an `axes`-axis bank: rates (incl. ±f/2 and
/// reversals), timings, modes, RUN masks (several axes at once), SNAPSHOT
/// strobes and reads of every address, including undecoded ones.
pub fn bank_stimulus(axes: u32, width: u32, clocks: usize, seed: u64) -> Vec<BankVector> {
    let map = motionhdl_model::regmap::pulse_bank(axes, width);
    let decoded: Vec<u32> = map.decoded().iter().map(|d| d.0).collect();
    let mut next = Rng::stream(seed);
    let mut v = vec![
        BankVector {
            reset: true,
            stops: m::Stops::default(),
            bus: BusCycle::default(),
            snapshot: false
        };
        4
    ];
    let mut halt_for = 0u64;
    let (mut up, mut down) = (0u32, 0u32);
    while v.len() < clocks {
        if halt_for == 0 && next().is_multiple_of(2000) {
            halt_for = 1 + next() % 40;
        }
        let halt = halt_for > 0;
        halt_for = halt_for.saturating_sub(1);
        // Direction stops come and go per axis, as limits and alarms do.
        if next().is_multiple_of(200) {
            up ^= 1 << (next() % u64::from(axes));
        }
        if next().is_multiple_of(200) {
            down ^= 1 << (next() % u64::from(axes));
        }
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
        // Home events: one-clock strobes on random axes.
        let home = if next().is_multiple_of(300) {
            1 << (next() % u64::from(axes))
        } else {
            0
        };
        v.push(BankVector {
            stops: m::Stops {
                halt,
                up,
                down,
                home,
            },
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
        uut.halt.next = v.stops.halt;
        uut.stop_up.next = u64::from(v.stops.up).into();
        uut.stop_down.next = u64::from(v.stops.down).into();
        uut.home_capture.next = u64::from(v.stops.home).into();
        settle(&mut uut);
        cycle(&mut uut, |u| &mut u.clock);
        model.clock_stopping(v.reset, &v.bus, v.snapshot, &v.stops);
        let got_rdata = uut.rdata.val().index() as u32;
        let mut bad = (got_rdata != model.rdata())
            .then(|| format!("rdata HDL {got_rdata:#x}, model {:#x}", model.rdata()));
        for i in 0..N {
            let (max, min) = model.soft_levels();
            let events = (
                uut.done.val().get_bit(i),
                uut.low.val().get_bit(i),
                uut.at_soft_max.val().get_bit(i),
                uut.at_soft_min.val().get_bit(i),
            );
            let want_events = (
                model.move_done(i),
                model.fifo_low(i),
                max >> i & 1 == 1,
                min >> i & 1 == 1,
            );
            if events != want_events {
                bad.get_or_insert(format!(
                    "axis {i}: (done, low, at_soft_max, at_soft_min) HDL {events:?}, model {want_events:?}"
                ));
            }
            let f = (uut.f1.val().get_bit(i), uut.f2.val().get_bit(i));
            let g = state_map::generator(uut.generator(i).probe());
            let mg = model.generator(i);
            let want_g = *mg;
            let e = state_map::engine(uut.engine(i).probe());
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
    let mut next = Rng::stream(seed);
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
    while pb.generator(0).status.val().get_bit(16) {
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
        motionhdl_model::counter::sign_extend(pb.generator(0).probe().position, W) as i32 as i64;
    (position, counted, clocks)
}

/// A position move in rust-hdl beside the model, every clock: an axis of a
/// 2-axis bank in MOVES mode gets `segments` pushed (more than the FIFO
/// holds, topped up as it drains, as firmware streams an S-curve), runs
/// until STATUS shows DONE and not BUSY, and the position must be the sum
/// of the segments' steps (signed by their direction). Returns the report, the
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
                state_map::engine(uut.engine(a).probe()),
                state_map::generator(uut.generator(a).probe()),
            );
            let g = model.generator(a);
            let want = (model.engine(a).probe(), *g);
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
            step(&mut uut, &mut model, w("SEG_JERK", seg.jerk as u32), &mut r);
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
        .map(|s| i64::from(s.steps) * motionhdl_firmware::segments::direction(s))
        .sum();
    r.expected = r.covered;
    (r, position, expected)
}

/// The bank's checks `motionhdl verify` runs.
pub fn all(_external: bool) -> Vec<CheckReport> {
    vec![bank_rust(100_000, 0x5eed_0004)]
}
