//! Pulse generator scenario traces: the rust-hdl pulse bank (one axis)
//! stepped beside its model (a mismatch aborts the trace), recording the
//! register bus, S1/S2, F1/F2 and the axis's queue and position.

use crate::harness::{cycle, settle};
use crate::state_map;
use crate::trace::{SignalId, Trace};
use motionhdl_hdl::{banner_ascii, PulseBank};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::pulse_generator as m;
use motionhdl_model::regmap::{self, Block as RegisterBlock};
use motionhdl_model::Config;
use rust_hdl::prelude::*;

struct Script {
    uut: PulseBank<1>,
    model: m::PulseBank,
    map: RegisterBlock,
    trace: Trace,
    half_ns: u64,
    t: u64,
    ids: [SignalId; 14],
}

impl Script {
    fn new(name: &str, config: &Config) -> Self {
        let width = config.counter_width();
        let mut trace = Trace::new(format!(
            "{} | scenario {name} | clock {} Hz",
            banner_ascii(),
            config.clock_hz()
        ));
        let top = ["pulse_bank"];
        let ax = ["pulse_bank", "ax0"];
        let ids = [
            trace.signal(&top, "clock", 1),
            trace.signal(&top, "addr", 8),
            trace.signal(&top, "wdata", 32),
            trace.signal(&top, "we", 1),
            trace.signal(&ax, "rate", 32),
            trace.signal(&ax, "s1_step", 1),
            trace.signal(&ax, "s2_dir", 1),
            trace.signal(&ax, "f1", 1),
            trace.signal(&ax, "f2", 1),
            trace.signal(&ax, "pending", 16),
            trace.signal(&ax, "position", 32),
            trace.signal(&ax, "ctrl", 3),
            trace.signal(&ax, "moving", 1),
            trace.signal(&ax, "done", 1),
        ];
        let mut uut = PulseBank::<1>::new(width);
        uut.connect_all();
        let half_ns = 500_000_000 / config.clock_hz();
        let mut s = Self {
            uut,
            model: m::PulseBank::new(1, width),
            map: regmap::pulse_bank(1, width),
            trace,
            half_ns: half_ns.max(1),
            t: 0,
            ids,
        };
        for _ in 0..4 {
            s.clock(BusCycle::default(), true);
        }
        s
    }

    fn clock(&mut self, bus: BusCycle, reset: bool) {
        let u = &mut self.uut;
        u.reset.next = reset;
        u.addr.next = u64::from(bus.addr).into();
        u.wdata.next = u64::from(bus.wdata).into();
        u.we.next = bus.we;
        u.re.next = bus.re;
        u.snapshot.next = false;
        settle(u);
        let t = self.t;
        let ids = self.ids;
        self.trace.set(t, ids[0], 0);
        self.trace.set(t, ids[1], u64::from(bus.addr));
        self.trace.set(t, ids[2], u64::from(bus.wdata));
        self.trace.set(t, ids[3], u64::from(bus.we));
        cycle(u, |u| &mut u.clock);
        self.model.clock(reset, &bus, false);
        let g = self.model.generator(0);
        let got = state_map::generator(u.generator(0).probe());
        assert_eq!(&got, g, "scenario: HDL and model disagree at {t} ns");
        let (position, timer) = (got.position, got.timer.state());
        let (f1, f2) = (u.f1.val().get_bit(0), u.f2.val().get_bit(0));
        assert_eq!((f1, f2), self.model.outputs(0));
        let t1 = t + self.half_ns;
        let rate = self
            .model
            .read_value(self.map.array("AX").address(0, "RATE"));
        let k = self
            .model
            .read_value(self.map.array("AX").address(0, "CTRL"));
        self.trace.set(t1, ids[0], 1);
        self.trace.set(t1, ids[4], u64::from(rate));
        self.trace.set(t1, ids[5], u64::from(timer.step));
        self.trace.set(t1, ids[6], u64::from(timer.dir));
        self.trace.set(t1, ids[7], u64::from(f1));
        self.trace.set(t1, ids[8], u64::from(f2));
        self.trace
            .set(t1, ids[9], u64::from(timer.pending as u32 & 0xffff));
        self.trace.set(t1, ids[10], u64::from(position));
        let status = self
            .model
            .read_value(self.map.array("AX").address(0, "STATUS"));
        self.trace.set(t1, ids[11], u64::from(k));
        self.trace.set(t1, ids[12], u64::from(status >> 17 & 1));
        self.trace.set(t1, ids[13], u64::from(status >> 18 & 1));
        self.t += 2 * self.half_ns;
    }

    fn write(&mut self, name: &str, data: u32) {
        let addr = match name {
            "RUN" => self.map.register("RUN").offset,
            r => self.map.array("AX").address(0, r),
        };
        self.clock(BusCycle::write(addr, data), false);
    }

    /// A named marker at the current clock (the next one recorded).
    fn mark(&mut self, name: &str) {
        self.trace.mark(self.t, name);
    }

    fn idle(&mut self, clocks: u32) {
        for _ in 0..clocks {
            self.clock(BusCycle::default(), false);
        }
    }

    fn setup(&mut self, ctrl: u32) {
        self.write("CTRL", ctrl);
        // STEP_LEN 2, STEP_SPACE 2; DIR_SETUP 3, DIR_HOLD 2 (clocks).
        self.write("STEP_TIMING", 2 | 2 << 16);
        self.write("DIR_TIMING", 3 | 2 << 16);
    }
}

/// A move through the segment FIFO: accelerate (the rate grows by
/// SEG_ACCEL, at its steepest, every clock), cruise, decelerate, then
/// STATUS.DONE.
pub fn acceleration(config: &Config) -> Trace {
    let mut s = Script::new("pulse_acceleration", config);
    s.setup(0b100);
    // f/256 up to about f/57 and back: the steepest SEG_ACCEL adds 2^15
    // rate LSBs a clock (2^-17 steps/clock²).
    let (k, steep) = (1 << 24, i32::MAX);
    // Push two, start (the first segment's copy out of the FIFO's RAM is
    // complete by then, so it loads at once), then push the third while
    // the first runs.
    for (i, (steps, rate, accel)) in [(20, k, steep), (20, 72 << 20, 0), (19, 72 << 20, -steep)]
        .into_iter()
        .enumerate()
    {
        if i == 2 {
            s.mark("RUN");
            s.write("RUN", 1);
        }
        s.write("SEG_STEPS", steps);
        s.write("SEG_RATE", rate as u32);
        s.write("SEG_ACCEL", accel as u32);
        s.write("SEG_JERK", 0);
        s.write("SEG_PUSH", 0);
    }
    s.idle(5_500);
    s.mark("DONE checked");
    let e = s.model.engine(0);
    assert!(
        e.done() && !e.overflow() && s.model.generator(0).position == 59,
        "pulse_acceleration: the move did not end on its 59 steps"
    );
    s.write("RUN", 0);
    s.idle(20);
    s.trace
}

/// Forward at f/8, then reversed, with CTRL = `ctrl` (0 pulse+direction,
/// 1 CW/CCW, 2 quadrature).
fn reversal_with(name: &str, config: &Config, ctrl: u32) -> Trace {
    let mut s = Script::new(name, config);
    s.setup(ctrl);
    s.write("RATE", 1 << 29);
    s.mark("RUN");
    s.write("RUN", 1);
    s.idle(80);
    s.mark("RATE reversed");
    s.write("RATE", (-(1i32 << 29)) as u32);
    s.idle(120);
    s.mark("RUN = 0");
    s.write("RUN", 0);
    s.idle(20);
    s.trace
}

/// Forward, then a reversal: S2 changes only after DIR_HOLD clocks with S1
/// low, and S1 rises again only after DIR_SETUP clocks.
pub fn reversal(config: &Config) -> Trace {
    reversal_with("pulse_reversal", config, 0)
}

/// Quadrature output (CTRL.QUADRATURE): F1/F2 = A/B, one edge per step,
/// A leading B forward and B leading A after the reversal.
pub fn quadrature(config: &Config) -> Trace {
    reversal_with("pulse_quadrature", config, 0b010)
}

/// The same reversal with the selector in CW/CCW: F1 carries the forward
/// pulses, F2 the reverse ones, with no runt at the switch.
pub fn cw_ccw(config: &Config) -> Trace {
    reversal_with("pulse_cw_ccw", config, 1)
}
