//! Named scenario traces, written by `motionhdl trace NAME` and by
//! `motionhdl generate` into `generated/vcd/`. Every value in a trace comes
//! from stepping the rust-hdl blocks; nothing is drawn from the model, but
//! for `servo_loop`, whose 3.1 M clocks run on the model of the servo
//! card's top (held to the rust-hdl top every clock by the checks; see
//! `servo_loop::trace`).

pub mod counter_bank;
pub mod isa_bridge;
pub mod pulse_generator;
pub mod servo_dac;

use crate::harness::settle;
use crate::trace::{SignalId, Trace};
use counter_bank as cs;
use motionhdl_hdl::{banner_ascii, Ls153, PulseModeSelector, PulseModeSelectorRegistered};
use motionhdl_model::Config;
use rust_hdl::prelude::*;

/// A scenario: its name and what it shows.
pub struct Scenario {
    pub name: &'static str,
    pub summary: &'static str,
    /// Whether the trace carries a plot (an `.svg` beside the `.vcd`).
    pub plot: bool,
    build: fn(&Config) -> Trace,
}

impl Scenario {
    pub fn trace(&self, config: &Config) -> Trace {
        let trace = (self.build)(config);
        assert_eq!(trace.plot().is_some(), self.plot, "{}: plot", self.name);
        trace
    }
}

/// Every scenario, in the order `motionhdl trace --help` lists them.
pub const SCENARIOS: &[Scenario] = &[
    Scenario {
        name: "pulse_mode_selector",
        summary: "all 8 (K,S2,S1) inputs in both modes, then pulse trains with a direction change, \
                  through the combinational and the registered selector",
        plot: false,
        build: pulse_mode_selector,
    },
    Scenario {
        name: "counter_slow_reversal",
        summary: "counter bank, X4: a slow encoder 12 steps forward and 8 back, then snapshot and read",
        plot: false,
        build: cs::slow_reversal,
    },
    Scenario {
        name: "counter_x4_x2_x1",
        summary: "counter bank: one encoder on three channels counting X4, X2 and X1 side by side",
        plot: false,
        build: cs::x4_x2_x1,
    },
    Scenario {
        name: "counter_pulse_dir",
        summary: "counter bank, pulse+direction: 5 pulses forward, 3 back",
        plot: false,
        build: cs::pulse_direction,
    },
    Scenario {
        name: "counter_cw_ccw",
        summary: "counter bank, CW/CCW: 5 pulses on A (up), 3 on B (down)",
        plot: false,
        build: cs::cw_ccw,
    },
    Scenario {
        name: "counter_index",
        summary: "counter bank: gated index latching every turn, then one-shot clear-on-index after ARM",
        plot: false,
        build: cs::index_latch_clear,
    },
    Scenario {
        name: "counter_illegal",
        summary: "counter bank: an illegal A+B transition latches ERR, the count holds, CLEAR_STATUS clears",
        plot: false,
        build: cs::illegal_transition,
    },
    Scenario {
        name: "counter_filter",
        summary: "counter bank, FILTER_AB=3: a 2-clock glitch on A is rejected, a real step accepted",
        plot: false,
        build: cs::filter_glitch,
    },
    Scenario {
        name: "pulse_acceleration",
        summary: "pulse generator: a move through the segment FIFO: accelerate, cruise, decelerate, DONE",
        plot: false,
        build: pulse_generator::acceleration,
    },
    Scenario {
        name: "pulse_reversal",
        summary: "pulse generator, pulse+direction: a reversal with direction hold and set-up visible",
        plot: false,
        build: pulse_generator::reversal,
    },
    Scenario {
        name: "pulse_cw_ccw",
        summary: "pulse generator, CW/CCW: the same reversal, F1 then F2 pulses, no runt at the switch",
        plot: false,
        build: pulse_generator::cw_ccw,
    },
    Scenario {
        name: "pulse_quadrature",
        summary: "pulse generator, quadrature output: A leads B forward, B leads A after the reversal",
        plot: false,
        build: pulse_generator::quadrature,
    },
    Scenario {
        name: "system",
        summary: "the whole controller: an S-curve on axis 0 and a follower at K = -1/2 on axis 1, \
                  streamed over FSMC, out to simulated drives, counted back from their encoders",
        plot: true,
        build: crate::checks::motion_controller::system::trace,
    },
    Scenario {
        name: "limit_stop",
        summary: "the whole controller: axis 0 creeps into a LIMIT_POS switch (1 us filter), stops \
                  on it with IRQ low, a move further in is refused, it backs off, the cause is cleared",
        plot: false,
        build: crate::checks::motion_controller::limit_stop::trace,
    },
    Scenario {
        name: "limit_brake",
        summary: "the whole controller: as limit_stop with AX.DECEL set: axis 0 brakes past the \
                  switch, the step spacing widening, to rest about v^2/2a beyond it; held, backed off, cleared",
        plot: false,
        build: crate::checks::motion_controller::limit_stop::brake_trace,
    },
    Scenario {
        name: "homing",
        summary: "the whole controller: the firmware's homing sequence on axis 0 over FSMC: fast search, \
                  back-off, slow search captured by HOME_POSITION/HOME_COUNT, on to the encoder index",
        plot: false,
        build: crate::checks::motion_controller::homing::trace,
    },
    Scenario {
        name: "estop",
        summary: "the whole controller: two axes creep, the e-stop chain opens: both stop, drives off, \
                  outputs safe, IRQ low; the chain closes, firmware clears the latch",
        plot: false,
        build: crate::checks::motion_controller::estop::trace,
    },
    Scenario {
        name: "watchdog_bite",
        summary: "the whole controller: two axes creep, firmware feeds the watchdog four times and \
                  stops; it bites, steps and drive enables stop, the outputs take their safe state, IRQ falls",
        plot: false,
        build: crate::checks::motion_controller::watchdog_bite::trace,
    },
    Scenario {
        name: "irq_refill",
        summary: "the whole controller: two axes stream 96 segments each, the firmware refilling \
                  the FIFOs on the FIFO-low interrupt alone, never reading STATUS",
        plot: false,
        build: crate::checks::motion_controller::irq_refill::trace,
    },
    Scenario {
        name: "isa_block_write",
        summary: "ISA bridge: the PC writes 8 words with AUTO_INC (real ISA timing, ps), the DSP reads them",
        plot: false,
        build: |_| isa_bridge::block_write_trace(),
    },
    Scenario {
        name: "isa_block_read",
        summary: "ISA bridge: the DSP writes 8 words, the PC reads 4 the seed's way (DATA, ADDR_INC) and 4 with AUTO_INC",
        plot: false,
        build: |_| isa_bridge::block_read_trace(),
    },
    Scenario {
        name: "isa_doorbell",
        summary: "ISA bridge: the DSP rings the PC through its mailbox word (IRQ up), the PC reads \
                  the mailbox (IRQ down) and the block, then rings the DSP back",
        plot: false,
        build: |_| isa_bridge::doorbell_trace(),
    },
    Scenario {
        name: "servo_dac",
        summary: "servo DAC block: a tick every 40 clocks, four new codes staged each period and \
                  written to the DAC pins after each tick, all four outputs moving at one \
                  LOADDACS rise; the safe input drives them to mid-scale (0 V)",
        plot: false,
        build: |_| servo_dac::trace(),
    },
    Scenario {
        name: "servo_loop",
        summary: "the servo card's loop closed: the PC sends a circle over ISA, the DSP's B-spline and \
                  PID run per tick, the DAC drives the motors, the rulers count back; one sample per \
                  tick, with a plot (.svg) of commanded versus measured position and the DAC outputs",
        plot: true,
        build: |_| crate::servo_loop::trace::trace(),
    },
];

/// Looks a scenario up by name.
pub fn find(name: &str) -> Option<&'static Scenario> {
    SCENARIOS.iter().find(|s| s.name == name)
}

/// Every scenario name, for error messages.
pub fn names() -> Vec<&'static str> {
    SCENARIOS.iter().map(|s| s.name).collect()
}

pub use crate::trace::half_period_ns;

struct ChipIds {
    pins: Vec<SignalId>,
}

impl ChipIds {
    const PINS: [&'static str; 14] = [
        "a", "b", "g1_n", "g2_n", "c1_0", "c1_1", "c1_2", "c1_3", "c2_0", "c2_1", "c2_2", "c2_3",
        "y1", "y2",
    ];
    fn new(trace: &mut Trace, scope: &[&str]) -> Self {
        Self {
            pins: Self::PINS
                .iter()
                .map(|p| trace.signal(scope, p, 1))
                .collect(),
        }
    }
    fn record(&self, trace: &mut Trace, t: u64, c: &Ls153) {
        let v = [
            c.a.val(),
            c.b.val(),
            c.g1_n.val(),
            c.g2_n.val(),
            c.c1_0.val(),
            c.c1_1.val(),
            c.c1_2.val(),
            c.c1_3.val(),
            c.c2_0.val(),
            c.c2_1.val(),
            c.c2_2.val(),
            c.c2_3.val(),
            c.y1.val(),
            c.y2.val(),
        ];
        for (id, v) in self.pins.iter().zip(v) {
            trace.set(t, *id, v.into());
        }
    }
}

/// One clock period per input vector (K, S2, S1): inputs change on the
/// falling edge, the registered selector samples them on the rising edge.
fn pulse_mode_selector(config: &Config) -> Trace {
    let mut trace = Trace::new(format!(
        "{} | scenario pulse_mode_selector | clock {} Hz",
        banner_ascii(),
        config.clock_hz()
    ));
    let comb_scope = ["pulse_mode_selector"];
    let reg_scope = ["pulse_mode_selector_registered"];
    let c = [
        trace.signal(&comb_scope, "k", 1),
        trace.signal(&comb_scope, "s1", 1),
        trace.signal(&comb_scope, "s2", 1),
        trace.signal(&comb_scope, "f1", 1),
        trace.signal(&comb_scope, "f2", 1),
    ];
    let chip = ChipIds::new(&mut trace, &["pulse_mode_selector", "chip"]);
    let r = [
        trace.signal(&reg_scope, "clock", 1),
        trace.signal(&reg_scope, "reset", 1),
        trace.signal(&reg_scope, "k", 1),
        trace.signal(&reg_scope, "s1", 1),
        trace.signal(&reg_scope, "s2", 1),
        trace.signal(&reg_scope, "f1", 1),
        trace.signal(&reg_scope, "f2", 1),
    ];
    let mut comb = PulseModeSelector::default();
    comb.connect_all();
    let mut reg = PulseModeSelectorRegistered::default();
    reg.connect_all();

    // (reset, K, S2, S1) per clock.
    let mut steps: Vec<(bool, bool, bool, bool)> = vec![(true, false, false, false); 2];
    for k in [false, true] {
        for m in 0..4u8 {
            steps.push((false, k, m & 2 != 0, m & 1 != 0));
        }
    }
    for k in [false, true] {
        steps.extend([(false, k, false, false); 2]);
        for dir in [false, true] {
            for _ in 0..3 {
                steps.push((false, k, dir, true));
                steps.push((false, k, dir, false));
            }
            steps.push((false, k, dir, false));
        }
        steps.extend([(false, k, false, false); 2]);
    }

    let half = half_period_ns(config);
    let mut t = 0;
    let record =
        |trace: &mut Trace, t: u64, comb: &PulseModeSelector, reg: &PulseModeSelectorRegistered| {
            for (id, v) in c.iter().zip([
                comb.k.val(),
                comb.s1.val(),
                comb.s2.val(),
                comb.f1.val(),
                comb.f2.val(),
            ]) {
                trace.set(t, *id, v.into());
            }
            chip.record(trace, t, comb.chip());
            let rv = [
                reg.clock.val().clk,
                reg.reset.val(),
                reg.k.val(),
                reg.s1.val(),
                reg.s2.val(),
                reg.f1.val(),
                reg.f2.val(),
            ];
            for (id, v) in r.iter().zip(rv) {
                trace.set(t, *id, v.into());
            }
        };
    for (reset, k, s2, s1) in steps {
        comb.k.next = k;
        comb.s2.next = s2;
        comb.s1.next = s1;
        settle(&mut comb);
        reg.reset.next = reset;
        reg.k.next = k;
        reg.s2.next = s2;
        reg.s1.next = s1;
        reg.clock.next = Clock::from(false);
        settle(&mut reg);
        record(&mut trace, t, &comb, &reg);
        t += half;
        reg.clock.next = Clock::from(true);
        settle(&mut reg);
        record(&mut trace, t, &comb, &reg);
        t += half;
    }
    reg.clock.next = Clock::from(false);
    settle(&mut reg);
    record(&mut trace, t, &comb, &reg);
    let k = "pulse_mode_selector.k";
    let table = trace.mark_edge(k, 1, 0, "all inputs, K = 1 (CW/CCW)");
    let trains = trace.mark_edge(k, 0, table, "trains, K = 0 (pulse+direction)");
    trace.mark_edge(k, 1, trains, "trains, K = 1 (CW/CCW)");
    trace
}
