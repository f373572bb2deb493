//! Counter bank scenario traces. Each runs the rust-hdl bank beside the
//! model (a mismatch aborts the trace) and records the bus, every pin and
//! each channel's accepted levels, count, index and flags.

use crate::checks::counter_bank::BankPair;
use crate::checks::counter_channel::ctrl_value;
use crate::trace::{SignalId, Trace};
use motionhdl_hdl::banner_ascii;
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap::{self, Block as RegisterBlock};
use motionhdl_model::Config;

/// Channels in every counter scenario (the default bank).
pub const AXES: usize = 4;

/// Pins of one channel for Gray phase 0..=3: (a, b) = 00, 10, 11, 01.
pub fn quadrature(phase: u8) -> (bool, bool) {
    let p = phase & 3;
    (p == 1 || p == 2, p == 2 || p == 3)
}

struct ChannelIds {
    pins: [SignalId; 3],
    levels: [SignalId; 3],
    count: SignalId,
    index: SignalId,
    flags: [SignalId; 4],
    err_count: SignalId,
    mode: SignalId,
}

/// A scenario being recorded.
pub struct Script {
    pair: BankPair<AXES>,
    map: RegisterBlock,
    trace: Trace,
    half_ns: u64,
    t: u64,
    pins: [(bool, bool, bool); AXES],
    bus_ids: [SignalId; 6],
    rdata_id: SignalId,
    ch_ids: Vec<ChannelIds>,
    width: u32,
}

impl Script {
    pub fn new(name: &str, config: &Config) -> Self {
        let width = config.counter_width();
        let mut trace = Trace::new(format!(
            "{} | scenario {name} | clock {} Hz",
            banner_ascii(),
            config.clock_hz()
        ));
        let top = ["counter_bank"];
        let bus_ids = [
            trace.signal(&top, "clock", 1),
            trace.signal(&top, "reset", 1),
            trace.signal(&top, "addr", 8),
            trace.signal(&top, "wdata", 32),
            trace.signal(&top, "we", 1),
            trace.signal(&top, "re", 1),
        ];
        let rdata = trace.signal(&top, "rdata", 32);
        let mut ch_ids = Vec::new();
        for i in 0..AXES {
            let name = format!("ch{i}");
            let s = ["counter_bank", name.as_str()];
            ch_ids.push(ChannelIds {
                pins: [
                    trace.signal(&s, "a", 1),
                    trace.signal(&s, "b", 1),
                    trace.signal(&s, "z", 1),
                ],
                levels: [
                    trace.signal(&s, "a_accepted", 1),
                    trace.signal(&s, "b_accepted", 1),
                    trace.signal(&s, "z_accepted", 1),
                ],
                count: trace.signal(&s, "count", width),
                index: trace.signal(&s, "index", width),
                flags: [
                    trace.signal(&s, "err", 1),
                    trace.signal(&s, "seen", 1),
                    trace.signal(&s, "armed", 1),
                    trace.signal(&s, "reverse", 1),
                ],
                err_count: trace.signal(&s, "err_count", regmap::ERR_COUNT_BITS),
                mode: trace.signal(&s, "mode", 3),
            });
        }
        let mut s = Self {
            pair: BankPair::new(width, regmap::ERR_COUNT_BITS),
            map: regmap::counter_bank(AXES as u32, width),
            trace,
            half_ns: crate::trace::half_period_ns(config),
            t: 0,
            pins: [(false, false, false); AXES],
            bus_ids,
            rdata_id: rdata,
            ch_ids,
            width,
        };
        s.step(true, BusCycle::default());
        s.step(true, BusCycle::default());
        s.step(true, BusCycle::default());
        s
    }

    fn record(&mut self, clock: bool, reset: bool, bus: &BusCycle) {
        let t = self.t;
        let v = [
            u64::from(clock),
            u64::from(reset),
            bus.addr.into(),
            bus.wdata.into(),
            bus.we.into(),
            bus.re.into(),
        ];
        for (id, v) in self.bus_ids.iter().zip(v) {
            self.trace.set(t, *id, v);
        }
        self.trace
            .set(t, self.rdata_id, self.pair.hdl.rdata.val().to_u64());
        let ctrl = self.map.array("CH").register("CTRL");
        for (i, ids) in self.ch_ids.iter().enumerate() {
            let p = self.pair.hdl.channel(i).probe();
            let pin = self.pins[i];
            for (id, v) in ids.pins.iter().zip([pin.0, pin.1, pin.2]) {
                self.trace.set(t, *id, v.into());
            }
            for (id, v) in ids.levels.iter().zip([p.fa.level, p.fb.level, p.fz.level]) {
                self.trace.set(t, *id, v.into());
            }
            self.trace.set(t, ids.count, p.count.into());
            self.trace.set(t, ids.index, p.index.into());
            let reverse = ctrl.field("REVERSE").get(p.ctrl) != 0;
            for (id, v) in ids.flags.iter().zip([p.err, p.seen, p.armed, reverse]) {
                self.trace.set(t, *id, v.into());
            }
            self.trace.set(t, ids.err_count, p.err_count.into());
            self.trace
                .set(t, ids.mode, ctrl.field("MODE").get(p.ctrl).into());
        }
    }

    /// One clock with the current pins and `bus`; records both clock phases.
    pub fn step(&mut self, reset: bool, bus: BusCycle) {
        self.record(false, reset, &bus);
        self.t += self.half_ns;
        if let Err(e) = self.pair.step(&self.pins, reset, &bus) {
            panic!("counter scenario: HDL and model disagree: {e}");
        }
        self.record(true, reset, &bus);
        self.t += self.half_ns;
    }

    /// Idle clocks.
    pub fn idle(&mut self, n: usize) {
        for _ in 0..n {
            self.step(false, BusCycle::default());
        }
    }

    /// Sets channel `ch`'s pins (held until changed).
    pub fn pins(&mut self, ch: usize, a: bool, b: bool, z: bool) {
        self.pins[ch] = (a, b, z);
    }

    pub fn write(&mut self, addr: u32, data: u32) {
        self.step(false, BusCycle::write(addr, data));
    }

    pub fn read(&mut self, addr: u32) -> u32 {
        self.step(false, BusCycle::read(addr));
        self.step(false, BusCycle::default());
        self.pair.hdl.rdata.val().to_u32()
    }

    pub fn ctrl(&mut self, ch: u32, fields: &[(&str, u32)]) {
        let v = ctrl_value(self.width, fields);
        let a = self.map.array("CH").address(ch, "CTRL");
        self.write(a, v);
    }

    pub fn cmd(&mut self, ch: u32, name: &str) {
        let m = self.map.array("CH").register("CMD").field(name).mask();
        let a = self.map.array("CH").address(ch, "CMD");
        self.write(a, m);
    }

    /// Snapshot, then read channel `ch`'s COUNT.
    pub fn snapshot_count(&mut self, ch: u32) -> u32 {
        let s = self.map.register("SNAPSHOT").offset;
        self.write(s, 0);
        let a = self.map.array("CH").address(ch, "COUNT");
        self.read(a)
    }

    pub fn live_count(&self, ch: usize) -> u32 {
        self.pair.hdl.channel(ch).probe().count
    }

    /// A named marker at the current clock (the next one recorded).
    pub fn mark(&mut self, name: &str) {
        self.trace.mark(self.t, name);
    }

    pub fn finish(mut self) -> Trace {
        self.idle(2);
        self.trace
    }
}

/// Moves an encoder on channels `chs` by `steps` Gray steps (negative =
/// backward), holding each state for `hold` clocks.
pub fn move_encoder(s: &mut Script, chs: &[usize], phase: &mut u8, steps: i32, hold: usize) {
    for _ in 0..steps.unsigned_abs() {
        *phase = if steps > 0 {
            phase.wrapping_add(1)
        } else {
            phase.wrapping_add(3)
        } & 3;
        let (a, b) = quadrature(*phase);
        for &c in chs {
            let z = s.pins[c].2;
            s.pins(c, a, b, z);
        }
        s.idle(hold);
    }
}

/// Slow encoder, X4: 12 steps forward, 8 back; the snapshot reads +4.
pub fn slow_reversal(config: &Config) -> Trace {
    let mut s = Script::new("counter_slow_reversal", config);
    s.ctrl(0, &[("MODE", regmap::mode::X4)]);
    let mut ph = 0;
    move_encoder(&mut s, &[0], &mut ph, 12, 6);
    s.mark("reversal");
    move_encoder(&mut s, &[0], &mut ph, -8, 6);
    s.idle(4);
    s.mark("SNAPSHOT");
    assert_eq!(s.snapshot_count(0), 4);
    s.finish()
}

/// The same encoder on three channels in X4, X2 and X1.
pub fn x4_x2_x1(config: &Config) -> Trace {
    let mut s = Script::new("counter_x4_x2_x1", config);
    s.ctrl(0, &[("MODE", regmap::mode::X4)]);
    s.ctrl(1, &[("MODE", regmap::mode::X2)]);
    s.ctrl(2, &[("MODE", regmap::mode::X1)]);
    let mut ph = 0;
    move_encoder(&mut s, &[0, 1, 2], &mut ph, 8, 4);
    s.idle(4);
    s.mark("reversal");
    assert_eq!(
        (s.live_count(0), s.live_count(1), s.live_count(2)),
        (8, 4, 2)
    );
    move_encoder(&mut s, &[0, 1, 2], &mut ph, -4, 4);
    s.idle(4);
    assert_eq!(
        (s.live_count(0), s.live_count(1), s.live_count(2)),
        (4, 2, 1)
    );
    s.finish()
}

/// Pulse + direction: 5 pulses forward, 3 back.
pub fn pulse_direction(config: &Config) -> Trace {
    let mut s = Script::new("counter_pulse_dir", config);
    s.ctrl(0, &[("MODE", regmap::mode::PULSE_DIR)]);
    for (n, dir) in [(5, false), (3, true)] {
        if dir {
            s.mark("direction reversed");
        }
        s.pins(0, false, dir, false);
        s.idle(3);
        for _ in 0..n {
            s.pins(0, true, dir, false);
            s.idle(3);
            s.pins(0, false, dir, false);
            s.idle(3);
        }
    }
    s.idle(4);
    assert_eq!(s.live_count(0), 2);
    s.finish()
}

/// CW/CCW: 5 pulses on A (up), 3 on B (down).
pub fn cw_ccw(config: &Config) -> Trace {
    let mut s = Script::new("counter_cw_ccw", config);
    s.ctrl(0, &[("MODE", regmap::mode::CW_CCW)]);
    for (n, on_b) in [(5, false), (3, true)] {
        if on_b {
            s.mark("pulses on B (down)");
        }
        for _ in 0..n {
            s.pins(0, !on_b, on_b, false);
            s.idle(3);
            s.pins(0, false, false, false);
            s.idle(3);
        }
    }
    s.idle(4);
    assert_eq!(s.live_count(0), 2);
    s.finish()
}

/// Index: latch on every index, then one-shot clear-on-index.
pub fn index_latch_clear(config: &Config) -> Trace {
    let mut s = Script::new("counter_index", config);
    s.ctrl(
        0,
        &[
            ("MODE", regmap::mode::X4),
            ("IDX_LATCH", 1),
            ("IDX_GATE", 1),
        ],
    );
    let mut ph = 0;
    // Index pulse while A and B are high (phase 2) on every turn.
    for turn in 1..=2 {
        move_encoder(&mut s, &[0], &mut ph, 2, 3);
        s.mark(&format!("index {turn} (latch)"));
        s.pins(0, true, true, true);
        s.idle(3);
        s.pins(0, true, true, false);
        move_encoder(&mut s, &[0], &mut ph, 2, 3);
    }
    s.ctrl(
        0,
        &[
            ("MODE", regmap::mode::X4),
            ("IDX_LATCH", 1),
            ("IDX_CLEAR", 1),
            ("IDX_GATE", 1),
            ("IDX_ONESHOT", 1),
        ],
    );
    s.mark("ARM");
    s.cmd(0, "ARM");
    for turn in 3..=4 {
        move_encoder(&mut s, &[0], &mut ph, 2, 3);
        let what = if turn == 3 { "clears" } else { "disarmed" };
        s.mark(&format!("index {turn} ({what})"));
        s.pins(0, true, true, true);
        s.idle(3);
        s.pins(0, true, true, false);
        move_encoder(&mut s, &[0], &mut ph, 2, 3);
    }
    s.idle(4);
    // Cleared at the first armed index only: 2 more steps in that turn and
    // 4 in the next (whose index no longer acts).
    assert_eq!(s.live_count(0), 6);
    s.finish()
}

/// An illegal transition: A and B change together; ERR latches, the count
/// holds; CLEAR_STATUS clears.
pub fn illegal_transition(config: &Config) -> Trace {
    let mut s = Script::new("counter_illegal", config);
    s.ctrl(0, &[("MODE", regmap::mode::X4), ("ERR_EN", 1)]);
    let mut ph = 0;
    move_encoder(&mut s, &[0], &mut ph, 3, 4);
    s.pins(0, false, false, false); // phase 3 -> 0 is legal; jump to 2 is not
    s.idle(4);
    s.mark("illegal transition");
    s.pins(0, true, true, false);
    s.idle(6);
    assert!(s.pair.hdl.channel(0).probe().err);
    assert_eq!(s.live_count(0), 4);
    s.mark("CLEAR_STATUS");
    s.cmd(0, "CLEAR_STATUS");
    s.idle(4);
    s.finish()
}

/// The filter at FILTER_AB = 3 rejects a 2-clock glitch on A and accepts a
/// real step.
pub fn filter_glitch(config: &Config) -> Trace {
    let mut s = Script::new("counter_filter", config);
    s.ctrl(0, &[("MODE", regmap::mode::X4), ("FILTER_AB", 3)]);
    s.idle(4);
    s.mark("glitch (2 clocks)");
    s.pins(0, true, false, false);
    s.idle(2);
    s.pins(0, false, false, false);
    s.idle(8);
    assert_eq!(s.live_count(0), 0);
    s.mark("step");
    s.pins(0, true, false, false);
    s.idle(10);
    assert_eq!(s.live_count(0), 1);
    s.finish()
}
