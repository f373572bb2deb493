//! The whole controller in simulation: firmware on the MCU plans a move
//! with the firmware crate's algorithms, streams it as segments over the
//! FSMC bus into the rust-hdl top, the pulse generators drive simulated
//! step/direction drives whose encoders feed the counter bank back, and the
//! firmware reads the counts over the same bus.
//!
//! Everything between the firmware and the drives is the top stepped clock
//! by clock, the rust-hdl `MotionController` or its generated Verilog in
//! Verilator ([`Engine`]); the firmware acts only through
//! the STM32F4 bus-functional model ([`crate::bfm::fsmc::timeline`]), one
//! FSMC access at a time, so it can poll STATUS and refill the FIFO as real
//! firmware does.

use super::motion_plot;
pub use super::top_engine::Engine;
use super::top_engine::Top;
use crate::bfm::fsmc::{documented_timing, timeline, Event, Op, CLOCK_TICKS, FIRST_EDGE_TICKS};
use crate::trace::{SignalId, Trace};
use motionhdl_firmware::segments::{direction, segments, SegmentConfig};
use motionhdl_model::fsmc_bridge::FsmcPins;
use motionhdl_model::machine_inputs::MachinePins;
use motionhdl_model::motion_controller::TopInputs;
use motionhdl_model::pulse_generator::{quadrature, Segment, SEGMENT_FIFO_DEPTH};
use motionhdl_model::regmap::{self, mode, BusMap};
use motionhdl_model::Config;
use std::collections::VecDeque;

/// Clocks from a step edge at the drive's input to its shaft moving.
pub const DRIVE_LATENCY: usize = 3;

/// A step/direction drive (pulse+direction: F1 = step, F2 = direction, 1 =
/// negative) with a quadrature encoder on its shaft, one encoder state per
/// step, so the counter bank counting ×4 reads the shaft position in steps.
#[derive(Clone, Debug)]
pub struct Drive {
    last_step: bool,
    /// Moves on their way through the drive's latency.
    pipeline: VecDeque<i32>,
    /// Shaft position, steps.
    pub position: i32,
}

impl Default for Drive {
    fn default() -> Self {
        Self {
            last_step: false,
            pipeline: VecDeque::from(vec![0; DRIVE_LATENCY]),
            position: 0,
        }
    }
}

impl Drive {
    /// One clock: sample the inputs, move the shaft.
    pub fn clock(&mut self, step: bool, dir: bool) {
        let rising = step && !self.last_step;
        self.last_step = step;
        self.pipeline.push_back(match (rising, dir) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => -1,
        });
        self.position = self
            .position
            .wrapping_add(self.pipeline.pop_front().unwrap_or(0));
    }

    /// Encoder A/B.
    pub fn encoder(&self) -> (bool, bool) {
        quadrature(self.position as u32)
    }
}

/// Per-axis waveforms for a trace: one scope per axis, plus the bus.
struct Probes {
    trace: Trace,
    half_ns: u64,
    /// The clock recorded at time 0.
    first_clock: u64,
    bus: [SignalId; 5],
    /// drive_enable, gpo_out, gpo_oe.
    machine: [SignalId; 3],
    axes: Vec<[SignalId; 9]>,
}

/// The MCU and the board around the top (in rust-hdl or Verilator, see
/// [`Engine`]): the firmware's bus accesses, the drives and encoders on
/// the pins.
pub struct System<const N: usize> {
    uut: Top<N>,
    /// The pins as last driven.
    inputs: TopInputs,
    map: BusMap,
    pub drives: Vec<Drive>,
    /// Clock edges simulated.
    pub clocks: u64,
    /// Largest |slave − K·master| seen, per follower (see [`Self::track`]).
    tracking: Vec<(usize, usize, i64, i64, i64)>,
    /// Shaft positions at every clock, when recording.
    pub path: Option<Vec<Vec<i32>>>,
    /// The clock after the last [`Self::run_move`]'s RUN write.
    pub run_at: Option<u64>,
    probes: Option<Probes>,
    /// The e-stop chain (high = released), as the board drives it.
    pub estop_ok: bool,
    /// Per axis, where a LIMIT_POS switch sits on the shaft: its pin is
    /// high (active high) while the shaft is at or beyond it.
    pub limit_pos_at: Vec<Option<i32>>,
    /// Per axis, a LIMIT_NEG switch: high at or below it.
    pub limit_neg_at: Vec<Option<i32>>,
    /// Per axis, a HOME switch: high at or beyond it.
    pub home_at: Vec<Option<i32>>,
    /// Per axis, the encoder's index: Z high at shaft positions that are
    /// multiples of it.
    pub index_every: Vec<Option<i32>>,
}

impl<const N: usize> System<N> {
    /// `config`'s controller on rust-hdl (what the traces are made with).
    pub fn new(config: &Config) -> Self {
        Self::on(Engine::RustHdl, config)
    }

    /// `config`'s controller on `engine`.
    pub fn on(engine: Engine, config: &Config) -> Self {
        assert_eq!(
            config.axes() as usize,
            N,
            "config axes vs MotionController<N>"
        );
        Self {
            uut: Top::new(engine, config),
            inputs: TopInputs::idle(),
            map: regmap::mcu_map(config),
            drives: vec![Drive::default(); N],
            clocks: 0,
            tracking: Vec::new(),
            path: None,
            run_at: None,
            probes: None,
            estop_ok: true,
            limit_pos_at: vec![None; N],
            limit_neg_at: vec![None; N],
            home_at: vec![None; N],
            index_every: vec![None; N],
        }
    }

    /// Record a VCD trace of the pins and shafts, one scope per axis.
    /// Recording starts now (after reset and setup): the trace's time 0 is
    /// this clock, which the banner names.
    pub fn record_trace(&mut self, banner: impl Into<String>, half_ns: u64) {
        let mut trace = Trace::new(format!(
            "{} | time 0 = clock {} after reset",
            banner.into(),
            self.clocks
        ));
        let bus = [
            trace.signal(&["fsmc"], "nwe_n", 1),
            trace.signal(&["fsmc"], "ne_n", 1),
            trace.signal(&["fsmc"], "a", 12),
            trace.signal(&["fsmc"], "d_in", 16),
            trace.signal(&["mcu"], "irq", 1),
        ];
        let machine = [
            trace.signal(&["machine"], "drive_enable", N as u32),
            trace.signal(&["machine"], "gpo_out", 16),
            trace.signal(&["machine"], "gpo_oe", 16),
        ];
        let axes = (0..N)
            .map(|i| {
                let scope = format!("axis{i}");
                let s = [scope.as_str()];
                [
                    trace.signal(&s, "pulse_f1_step", 1),
                    trace.signal(&s, "pulse_f2_dir", 1),
                    trace.signal(&s, "enc_a", 1),
                    trace.signal(&s, "enc_b", 1),
                    trace.analog(&s, "shaft_position", 32),
                    trace.signal(&s, "limit_pos", 1),
                    trace.signal(&s, "limit_neg", 1),
                    trace.signal(&s, "home", 1),
                    trace.signal(&s, "enc_z", 1),
                ]
            })
            .collect();
        self.probes = Some(Probes {
            trace,
            half_ns,
            first_clock: self.clocks,
            bus,
            machine,
            axes,
        });
    }

    /// Records trace scenario `name` of `config` (its banner and clock).
    pub fn record_scenario(&mut self, config: &Config, name: &str) {
        self.record_trace(
            format!(
                "{} | scenario {name} | clock {} Hz",
                motionhdl_hdl::banner_ascii(),
                config.clock_hz()
            ),
            crate::trace::half_period_ns(config),
        );
    }

    /// A named marker in the trace at the current clock.
    pub fn mark(&mut self, name: &str) {
        if let Some(p) = &mut self.probes {
            let t = (self.clocks - p.first_clock) * 2 * p.half_ns;
            p.trace.mark(t, name);
        }
    }

    /// A named marker at the first edge of `path` to `value` at or after
    /// `after` in the trace (see [`Trace::mark_edge`]); its time.
    pub fn mark_edge(&mut self, path: &str, value: u64, after: u64, name: &str) -> u64 {
        let p = self.probes.as_mut().expect("recording a trace");
        p.trace.mark_edge(path, value, after, name)
    }

    /// The recorded trace.
    pub fn take_trace(&mut self) -> Option<Trace> {
        self.probes.take().map(|p| p.trace)
    }

    /// Watch `slave` follow `master` at ratio num/den: the largest
    /// |slave·den − num·master| over every clock (see [`Self::tracking`]).
    pub fn track(&mut self, master: usize, slave: usize, num: i64, den: i64) {
        self.tracking.push((master, slave, num, den, 0));
    }

    /// (master, slave, num, den, largest |slave·den − num·master|).
    pub fn tracking(&self) -> &[(usize, usize, i64, i64, i64)] {
        &self.tracking
    }

    fn drive_pins(&mut self, pins: &FsmcPins, reset: bool) {
        let mut enc = [0u16; 3];
        let mut machine = MachinePins::default();
        for (k, d) in self.drives.iter().enumerate() {
            let (ea, eb) = d.encoder();
            let z = self.index_every[k].is_some_and(|n| d.position % n == 0);
            for (word, level) in enc.iter_mut().zip([ea, eb, z]) {
                *word |= u16::from(level) << k;
            }
            let pos = self.limit_pos_at[k].is_some_and(|at| d.position >= at);
            let neg = self.limit_neg_at[k].is_some_and(|at| d.position <= at);
            let home = self.home_at[k].is_some_and(|at| d.position >= at);
            machine.limit_pos |= u32::from(pos) << k;
            machine.limit_neg |= u32::from(neg) << k;
            machine.home |= u32::from(home) << k;
        }
        let i = TopInputs {
            reset,
            fsmc_ne_n: pins.ne_n,
            fsmc_noe_n: pins.noe_n,
            fsmc_nwe_n: pins.nwe_n,
            fsmc_a: pins.a,
            fsmc_d_in: pins.d_in,
            // The PC side idles: no strobes, AEN high (never our cycle).
            isa_aen: true,
            enc_a: enc[0],
            enc_b: enc[1],
            enc_z: enc[2],
            estop_ok: self.estop_ok,
            machine,
            ..TopInputs::idle()
        };
        self.inputs = i;
        self.uut.drive(&i);
    }

    /// One clock edge with these pins; then the drives see the outputs.
    fn edge(&mut self, pins: &FsmcPins, reset: bool) {
        self.drive_pins(pins, reset);
        self.uut.cycle();
        let out = self.uut.outputs();
        let (f1, f2) = (u64::from(out.pulse_f1), u64::from(out.pulse_f2));
        for (i, d) in self.drives.iter_mut().enumerate() {
            d.clock(f1 >> i & 1 != 0, f2 >> i & 1 != 0);
        }
        for t in &mut self.tracking {
            let (m, s) = (self.drives[t.0].position, self.drives[t.1].position);
            let err = (i64::from(s) * t.3 - t.2 * i64::from(m)).abs();
            t.4 = t.4.max(err);
        }
        if let Some(path) = &mut self.path {
            path.push(self.drives.iter().map(|d| d.position).collect());
        }
        if let Some(p) = &mut self.probes {
            let t = (self.clocks - p.first_clock) * 2 * p.half_ns;
            p.trace.set(t, p.bus[0], u64::from(pins.nwe_n));
            p.trace.set(t, p.bus[1], u64::from(pins.ne_n));
            p.trace.set(t, p.bus[2], u64::from(pins.a & 0xfff));
            p.trace.set(t, p.bus[3], u64::from(pins.d_in));
            p.trace.set(t, p.bus[4], u64::from(out.irq));
            let machine = [out.drive_enable, out.gpo_out, out.gpo_oe];
            for (id, v) in p.machine.into_iter().zip(machine) {
                p.trace.set(t, id, u64::from(v));
            }
            let (i, m) = (&self.inputs, &self.inputs.machine);
            for (k, d) in self.drives.iter().enumerate() {
                let (ea, eb) = d.encoder();
                let ids = p.axes[k];
                p.trace.set(t, ids[0], f1 >> k & 1);
                p.trace.set(t, ids[1], f2 >> k & 1);
                p.trace.set(t, ids[2], u64::from(ea));
                p.trace.set(t, ids[3], u64::from(eb));
                p.trace.set_quantity(t, ids[4], i64::from(d.position));
                p.trace.set(t, ids[5], u64::from(m.limit_pos >> k & 1));
                p.trace.set(t, ids[6], u64::from(m.limit_neg >> k & 1));
                p.trace.set(t, ids[7], u64::from(m.home >> k & 1));
                p.trace.set(t, ids[8], u64::from(i.enc_z >> k & 1));
            }
        }
        self.clocks += 1;
    }

    /// Runs one firmware bus operation to its end; a read returns what the
    /// MCU latched (the halfwords, low first).
    pub fn exec(&mut self, op: Op) -> Vec<u16> {
        let (events, end) = timeline(&[op], &documented_timing());
        // The BFM's time 0 sits just after a falling edge: each op starts
        // where the last one ended, on the same clock grid.
        let mut pins = FsmcPins::idle();
        let mut reset = false;
        let mut observed: Vec<u16> = Vec::new();
        let mut edge = FIRST_EDGE_TICKS;
        let mut i = 0;
        loop {
            while i < events.len() && events[i].0 < edge {
                match events[i].1 {
                    Event::Pins(p, r) => {
                        pins = p;
                        reset = r;
                    }
                    Event::ObserveSetup => {}
                    Event::ObserveEnd => {
                        self.drive_pins(&pins, reset);
                        observed.push(self.uut.outputs().fsmc_d_out);
                    }
                }
                i += 1;
            }
            if edge > end {
                break;
            }
            self.edge(&pins, reset);
            edge += CLOCK_TICKS;
        }
        observed
    }

    fn word(&self, block: &str, axis: Option<u32>, reg: &str) -> u16 {
        let b = self.map.block(block);
        let array = if block == "COUNTER" { "CH" } else { "AX" };
        let w = match axis {
            Some(i) => b.base + b.array(array).address(i, reg),
            None => b.base + b.register(reg).offset,
        };
        (w * 2) as u16
    }

    pub fn write(&mut self, block: &str, axis: Option<u32>, reg: &str, data: u32) {
        let a = self.word(block, axis, reg);
        self.exec(Op::Write32 { a, data });
    }

    pub fn read(&mut self, block: &str, axis: Option<u32>, reg: &str) -> u32 {
        let a = self.word(block, axis, reg);
        let h = self.exec(Op::Read32 { a });
        assert_eq!(h.len(), 2, "a 32-bit read is two halfwords");
        u32::from(h[0]) | u32::from(h[1]) << 16
    }

    /// Idle the bus for `clocks` clocks (the firmware busy elsewhere).
    pub fn idle(&mut self, clocks: u64) {
        let pins = FsmcPins::idle();
        for _ in 0..clocks {
            self.edge(&pins, false);
        }
    }

    /// Reset the FPGA and set every axis up: the e-stop latch (set by the
    /// reset) released, counters ×4, pulse generators in segment moves with
    /// pulse+direction output.
    pub fn setup(&mut self) {
        self.exec(Op::Reset);
        self.write("SAFETY", None, "CLEAR", 1);
        for i in 0..N as u32 {
            self.write("COUNTER", Some(i), "CTRL", mode::X4);
            self.write("PULSE", Some(i), "CTRL", 0b100);
            // STEP_LEN 2, STEP_SPACE 2; DIR_SETUP 4, DIR_HOLD 2 (clocks).
            self.write("PULSE", Some(i), "STEP_TIMING", 2 | 2 << 16);
            self.write("PULSE", Some(i), "DIR_TIMING", 4 | 2 << 16);
        }
    }

    /// The register map the firmware addresses.
    pub fn map(&self) -> &BusMap {
        &self.map
    }

    /// The drive ENABLE pins, bit i = axis i.
    pub fn drive_enable(&self) -> u32 {
        u32::from(self.uut.outputs().drive_enable)
    }

    /// The general-purpose output pins: (levels, drive enables).
    pub fn gpo(&self) -> (u32, u32) {
        let out = self.uut.outputs();
        (u32::from(out.gpo_out), u32::from(out.gpo_oe))
    }

    /// The IRQ pin.
    pub fn irq(&self) -> bool {
        self.uut.outputs().irq
    }

    /// Pushes one segment to `axis`'s FIFO, as firmware does: the four
    /// SEG_* words, then SEG_PUSH.
    pub fn push(&mut self, axis: u32, s: &Segment) {
        self.write("PULSE", Some(axis), "SEG_STEPS", s.steps);
        self.write("PULSE", Some(axis), "SEG_RATE", s.rate as u32);
        self.write("PULSE", Some(axis), "SEG_ACCEL", s.accel as u32);
        self.write("PULSE", Some(axis), "SEG_JERK", s.jerk as u32);
        self.write("PULSE", Some(axis), "SEG_PUSH", 0);
    }

    /// Streams each axis's segments as the firmware does: fill the FIFOs,
    /// start every axis in one RUN write, then poll STATUS.FIFO_LEVEL and
    /// top up; wait until every axis is DONE and not BUSY. Fails on a FIFO
    /// overflow or when the move does not finish within `timeout` clocks.
    pub fn run_move(&mut self, per_axis: &[Vec<Segment>], timeout: u64) -> Result<(), String> {
        assert_eq!(per_axis.len(), N);
        let status = self
            .map
            .block("PULSE")
            .array("AX")
            .register("STATUS")
            .clone();
        let mut next = vec![0usize; N];
        for (i, segs) in per_axis.iter().enumerate() {
            while next[i] < segs.len() && next[i] < SEGMENT_FIFO_DEPTH {
                self.push(i as u32, &segs[next[i]]);
                next[i] += 1;
            }
        }
        let mask = (0..N)
            .filter(|&i| !per_axis[i].is_empty())
            .fold(0, |m, i| m | 1 << i);
        self.write("PULSE", None, "RUN", mask);
        let start = self.clocks;
        self.run_at = Some(start);
        loop {
            let mut finished = true;
            for (i, segs) in per_axis.iter().enumerate() {
                if segs.is_empty() {
                    continue;
                }
                let s = self.read("PULSE", Some(i as u32), "STATUS");
                if status.field("OVERFLOW").get(s) != 0 {
                    return Err(format!("axis {i}: segment FIFO overflow"));
                }
                let level = status.field("FIFO_LEVEL").get(s) as usize;
                for _ in level..SEGMENT_FIFO_DEPTH {
                    if next[i] < segs.len() {
                        self.push(i as u32, &segs[next[i]]);
                        next[i] += 1;
                    }
                }
                let done = status.field("DONE").get(s) != 0 && status.field("BUSY").get(s) == 0;
                finished &= next[i] == segs.len() && done;
            }
            if finished {
                break;
            }
            if self.clocks - start > timeout {
                return Err(format!("the move did not finish in {timeout} clocks"));
            }
        }
        Ok(())
    }

    /// SNAPSHOT, then every axis's (COUNT, POSITION) read over the bus.
    pub fn positions(&mut self) -> Vec<(i32, i32)> {
        self.write("COUNTER", None, "SNAPSHOT", 0);
        (0..N as u32)
            .map(|i| {
                (
                    self.read("COUNTER", Some(i), "COUNT") as i32,
                    self.read("PULSE", Some(i), "POSITION") as i32,
                )
            })
            .collect()
    }
}

/// Whole-step positions per tick → segments at `tick_hz` on a 50 MHz
/// clock (the model's converter).
pub fn plan_segments(steps: &[i64], clock_hz: u32, tick_hz: u32) -> Vec<Segment> {
    segments(
        steps,
        0,
        SegmentConfig {
            clock_hz,
            tick_hz,
            phase: 0,
        },
    )
    .expect("profile within the NCO's range")
}

/// Signed steps of a segment list.
pub fn net_steps(segs: &[Segment]) -> i64 {
    segs.iter().map(|s| i64::from(s.steps) * direction(s)).sum()
}

/// `motionhdl trace system`: an S-curve of 200 steps on axis 0 with axis 1
/// following at K = −1/2, planned by the model, streamed over the FSMC bus
/// and counted back; two axes of the configuration's counter width and
/// clock. One scope per axis (pulse, direction, encoder, shaft) and one for
/// the bus; the `.gtkw` beside it opens them as groups.
pub fn trace(config: &Config) -> Trace {
    trace_on(Engine::RustHdl, config)
}

/// [`trace`] with the top in `engine`.
pub fn trace_on(engine: Engine, config: &Config) -> Trace {
    let two = Config::new(2, config.counter_width().into(), config.clock_hz())
        .expect("2 axes of a valid configuration");
    let clock_hz = u32::try_from(config.clock_hz()).expect("clock_hz fits u32");
    let tick_hz = clock_hz / 500;
    // The profile is the same in clocks at every clock rate (its physical
    // limits scale with the tick), and 200 steps unless the counters are
    // too narrow to count them back (then a quarter of their range).
    let scale = f64::from(tick_hz) / 100_000.0;
    let distance = 200.min(1i64 << (config.counter_width() - 2));
    let p = motionhdl_firmware::scurve::SCurveParams::from_physical(
        8e13 * scale * scale * scale,
        4e9 * scale * scale,
        2e6 * scale,
        distance,
        f64::from(tick_hz),
    );
    let samples: Vec<_> = motionhdl_firmware::scurve::SCurve::new(p)
        .expect("the trace's S-curve is within range")
        .samples()
        .collect();
    let master: Vec<i64> = samples.iter().map(|s| s.steps()).collect();
    let follower: Vec<i64> = master.iter().map(|m| (-m).div_euclid(2)).collect();
    let mut sys = System::<2>::on(engine, &two);
    sys.setup();
    sys.record_trace(
        format!(
            "{} | scenario system | clock {} Hz",
            motionhdl_hdl::banner_ascii(),
            config.clock_hz()
        ),
        crate::trace::half_period_ns(config),
    );
    sys.path = Some(Vec::new());
    let recording_from = sys.clocks;
    sys.run_move(
        &[
            plan_segments(&master, clock_hz, tick_hz),
            plan_segments(&follower, clock_hz, tick_hz),
        ],
        10_000_000,
    )
    .expect("the traced move finishes");
    let p = sys.positions();
    let d = distance as i32;
    assert_eq!(
        p,
        vec![(d, d), (-d / 2, -d / 2)],
        "system trace: counted back"
    );
    // Each drive's position from the RUN write on, for the plot.
    let from = (sys.run_at.expect("run_move writes RUN") - recording_from) as usize;
    let path = sys.path.take().expect("recorded");
    let executed: Vec<Vec<i32>> = (0..2)
        .map(|i| path[from..].iter().map(|at| at[i]).collect())
        .collect();
    let master_name = format!("axis 0 (S-curve, {distance} steps)");
    let plans = [
        motion_plot::Plan {
            name: &master_name,
            samples: &samples,
            scale: 1.0,
        },
        motion_plot::Plan {
            name: "axis 1 (follower, K = -1/2)",
            samples: &samples,
            scale: -0.5,
        },
    ];
    let mut trace = sys.take_trace().expect("recording");
    let half = crate::trace::half_period_ns(config);
    trace.mark(from as u64 * 2 * half, "RUN (both axes start)");
    trace.set_plot(motion_plot::svg(
        &motionhdl_hdl::banner(),
        &plans,
        &executed,
        u64::from(clock_hz / tick_hz),
        clock_hz,
    ));
    trace
}

/// The two-axis controller the trace scenarios run: `config`'s counter
/// width and clock, `adjust` for the rest, set up ([`System::setup`]).
pub fn two_axes(config: &Config, adjust: impl FnOnce(Config) -> Config) -> System<2> {
    two_axes_on(Engine::RustHdl, config, adjust)
}

/// [`two_axes`] with the top in `engine`.
pub fn two_axes_on(
    engine: Engine,
    config: &Config,
    adjust: impl FnOnce(Config) -> Config,
) -> System<2> {
    let two = Config::new(2, config.counter_width().into(), config.clock_hz())
        .expect("2 axes of a valid configuration");
    let mut sys = System::<2>::on(engine, &adjust(two));
    sys.setup();
    sys
}
