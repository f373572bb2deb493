//! The safety block's contract, stated from its pins, its bus and its
//! interrupt registers alone (never from the model), checked over a run
//! of the HDL. Each property counts the clocks where its antecedent held,
//! and [`Breakage`] shows each one able to fail.

use super::{Observed, AXES, TICK_CLOCKS};
use crate::harness::CheckReport;
use motionhdl_model::digital_io::GpoPins;
use motionhdl_model::machine_inputs::FILTER_TICKS;
use motionhdl_model::regmap;
use motionhdl_model::safety_io::{ESTOP_LATENCY, IRQ_LATENCY};

/// The properties, in the order [`contract`] reports them.
pub const PROPERTIES: [&str; 10] = [
    "IRQ pin = OR(cause AND mask) with its polarity, IRQ_LATENCY later",
    "no drive ENABLE while HALT",
    "an e-stop input low halts every axis ESTOP_LATENCY edges later",
    "HALT falls only at a CLEAR write",
    "an armed watchdog left alone bites exactly TIMEOUT + 1 edges after the arm",
    "a filtered input changes only after its pin read the new level at FILTER_TICKS ticks",
    "a pin held FILTER_TICKS x P + 2 clocks has passed its filter",
    "nothing latches from a disabled input",
    "while HALT every general-purpose output shows its safe state",
    "a GPI cause rises only at a selected edge of its filtered input",
];

/// Clocks from a pin sample to the filter tick that uses it (the two
/// synchroniser flip-flops).
const SYNC: usize = 2;

fn wrote(o: &Observed, offset: u32) -> bool {
    o.vector.bus.we && super::word_address(o.vector.bus.addr) == offset
}

/// Every property over `trace`: one report each, a case per antecedent.
pub fn contract(trace: &[Observed]) -> Vec<CheckReport> {
    let map = regmap::safety_io(AXES as u32);
    let offset = |name: &str| map.register(name).offset;
    let watchdog_bit = map.register("CAUSE").field("WATCHDOG").mask();
    let mut r: Vec<CheckReport> = PROPERTIES
        .iter()
        .map(|p| CheckReport::new("safety_io", p, 0))
        .collect();
    let latency = IRQ_LATENCY as usize;
    for k in latency..trace.len() {
        if (k + 1 - latency..=k).any(|j| trace[j].vector.reset) {
            continue;
        }
        let before = &trace[k - latency].registers;
        let want = before.irq_active() == before.active_high;
        r[0].case((trace[k].outputs.irq != want).then(|| {
            format!(
                "clock {k}: IRQ pin {}, registers before {before:?}",
                trace[k].outputs.irq
            )
        }));
    }
    for (k, o) in trace.iter().enumerate() {
        let out = o.outputs;
        if out.halt {
            r[1].case(
                (out.drive_enable != 0)
                    .then(|| format!("clock {k}: HALT, ENABLE {:#x}", out.drive_enable)),
            );
        }
    }
    let edges = ESTOP_LATENCY as usize;
    for k in 0..trace.len().saturating_sub(edges) {
        let window = &trace[k..k + edges];
        if trace[k].vector.inputs.estop_ok || window.iter().any(|o| o.vector.reset) {
            continue;
        }
        let halted = trace[k + edges - 1].outputs.halt;
        r[2].case(
            (!halted)
                .then(|| format!("input low at clock {k}, no HALT at clock {}", k + edges - 1)),
        );
    }
    let clear = offset("CLEAR");
    for k in 1..trace.len() {
        if trace[k - 1].outputs.halt && !trace[k].outputs.halt {
            let ok = wrote(&trace[k], clear) && trace[k].vector.bus.wdata & 3 != 0;
            r[3].case((!ok).then(|| format!("clock {k}: HALT fell at {:?}", trace[k].vector)));
        }
    }
    let (timeout, reload, cause) = (offset("WDT_TIMEOUT"), offset("WDT_RELOAD"), offset("CAUSE"));
    for e in 0..trace.len() {
        let t = trace[e].vector.bus.wdata as usize;
        if !wrote(&trace[e], timeout) || trace[e].vector.reset || t == 0 || e + t + 1 >= trace.len()
        {
            continue;
        }
        let window = &trace[e + 1..=e + t + 1];
        let disturbed = window
            .iter()
            .any(|o| o.vector.reset || wrote(o, timeout) || wrote(o, reload) || wrote(o, cause));
        if disturbed || trace[e].registers.cause & watchdog_bit != 0 {
            continue;
        }
        let early = trace[e + t].registers.cause & watchdog_bit != 0;
        let bit = trace[e + t + 1].registers.cause & watchdog_bit != 0;
        let halted = trace[e + t + 1].outputs.halt;
        r[4].case((early || !bit || !halted).then(|| {
            format!("armed with {t} at clock {e}: cause early {early}, at {}: cause {bit}, HALT {halted}", e + t + 1)
        }));
    }
    machine_properties(trace, &mut r[5..8]);
    gpio_properties(trace, &mut r[8..]);
    for report in &mut r {
        report.expected = report.covered;
    }
    r
}

/// Pin `kind` of axis `i` in vector `k`, and its filtered level after edge k.
fn pin(trace: &[Observed], k: usize, kind: usize, i: usize) -> bool {
    trace[k].vector.inputs.machine.kinds()[kind] >> i & 1 == 1
}

fn level(trace: &[Observed], k: usize, kind: usize, i: usize) -> bool {
    trace[k].registers.levels[kind] >> i & 1 == 1
}

/// The filter and enable properties, reports 5..=7.
fn machine_properties(trace: &[Observed], r: &mut [CheckReport]) {
    let p = TICK_CLOCKS as usize;
    let ticks = FILTER_TICKS as usize;
    let hold = ticks * p + SYNC;
    for k in hold..trace.len() {
        if trace[k - hold..=k].iter().any(|o| o.vector.reset) {
            continue;
        }
        for kind in 0..4 {
            for i in 0..AXES {
                let now = level(trace, k, kind, i);
                if now != level(trace, k - 1, kind, i) {
                    let samples: Vec<usize> = (0..ticks).map(|m| k - SYNC - m * p).collect();
                    let read = samples.iter().all(|&j| pin(trace, j, kind, i) == now);
                    r[0].case((!read).then(|| {
                        format!("clock {k}: input {kind} axis {i} became {now} without the pin at {samples:?}")
                    }));
                }
                let held = pin(trace, k, kind, i);
                if (k + 1 - hold..=k).all(|j| pin(trace, j, kind, i) == held) {
                    r[1].case((now != held).then(|| {
                        format!("clock {k}: input {kind} axis {i} pin {held} for {hold} clocks, level {now}")
                    }));
                }
            }
        }
    }
    // A cause bit rising must come from an enabled input: LIMIT_CAUSE's
    // halves from LIMIT_POS/NEG, HOME_ALARM_CAUSE's from HOME/ALARM.
    for k in 1..trace.len() {
        if trace[k].vector.reset || trace[k - 1].vector.reset {
            continue;
        }
        let (before, after) = (&trace[k - 1].registers, &trace[k].registers);
        let risen = [
            after.limit_cause & !before.limit_cause,
            after.home_alarm_cause & !before.home_alarm_cause,
        ];
        for (cause, rose) in risen.into_iter().enumerate() {
            for half in 0..2 {
                let bits = rose >> (16 * half) & 0xffff;
                if bits == 0 {
                    continue;
                }
                let enable = before.input_ctrl[2 * cause + half] & 0xffff;
                r[2].case((bits & !enable != 0).then(|| {
                    format!("clock {k}: cause {cause} half {half} rose {bits:#x} with ENABLE {enable:#x}")
                }));
            }
        }
    }
}

/// The general-purpose I/O properties, reports 8 and 9.
fn gpio_properties(trace: &[Observed], r: &mut [CheckReport]) {
    // Indices into SafetyRegisters::gpio.
    const LEVEL: usize = 0;
    const EDGES: usize = 1;
    const CAUSE: usize = 2;
    const SAFE: usize = 5;
    const OPEN_DRAIN: usize = 6;
    for k in 2..trace.len() {
        if trace[k - 2..=k].iter().any(|o| o.vector.reset) {
            continue;
        }
        // The value takes GPO_SAFE as it stood before the edge.
        let (safe, od) = (
            trace[k - 1].registers.gpio[SAFE],
            trace[k].registers.gpio[OPEN_DRAIN],
        );
        if trace[k - 1].outputs.halt && trace[k].outputs.halt {
            let want = GpoPins {
                out: safe & !od & 0xffff,
                oe: (!od | !safe) & 0xffff,
            };
            let got = trace[k].outputs.gpo;
            r[0].case(
                (got != want)
                    .then(|| format!("clock {k}: halted, outputs {got:?}, safe state {want:?}")),
            );
        }
        // A cause set at edge k comes from the levels before edges k and
        // k - 1 and the edges selected before edge k.
        let (g1, g2) = (&trace[k - 1].registers.gpio, &trace[k - 2].registers.gpio);
        let rose = trace[k].registers.gpio[CAUSE] & !g1[CAUSE];
        if rose != 0 {
            let edge =
                (g1[LEVEL] & !g2[LEVEL] & g1[EDGES]) | (!g1[LEVEL] & g2[LEVEL] & g1[EDGES] >> 16);
            r[1].case(
                (rose & !edge != 0).then(|| {
                    format!("clock {k}: GPI_CAUSE rose {rose:#x}, selected edges {edge:#x}")
                }),
            );
        }
    }
}

/// A deliberate fault in a good trace, one per property, to show each
/// property can fail.
#[derive(Clone, Copy, Debug)]
pub enum Breakage {
    /// The IRQ pin inverted at one clock.
    IrqFlipped,
    /// An ENABLE output high in a halted clock.
    EnableWhileHalted,
    /// HALT late after an e-stop input.
    EstopLate,
    /// HALT dropped for one clock in the middle of a halted stretch.
    HaltGlitch,
    /// The watchdog's cause one clock late.
    BiteLate,
    /// A filtered level flipped with no pin behind it.
    LevelFromNothing,
    /// A filtered level that stays behind its pin.
    LevelStuck,
    /// A limit cause rising while its input was disabled.
    CauseWhileDisabled,
    /// An output released in a halted clock.
    OutputNotSafe,
    /// A GPI cause rising with its edge not selected.
    GpiCauseUnselected,
}

impl Breakage {
    pub const ALL: [Breakage; 10] = [
        Breakage::IrqFlipped,
        Breakage::EnableWhileHalted,
        Breakage::EstopLate,
        Breakage::HaltGlitch,
        Breakage::BiteLate,
        Breakage::LevelFromNothing,
        Breakage::LevelStuck,
        Breakage::CauseWhileDisabled,
        Breakage::OutputNotSafe,
        Breakage::GpiCauseUnselected,
    ];

    /// The property (index into [`PROPERTIES`]) this breakage must fail.
    pub fn property(self) -> usize {
        self as usize
    }

    /// `trace` with the fault, at the first place it applies.
    pub fn apply(self, trace: &[Observed]) -> Vec<Observed> {
        let mut t = trace.to_vec();
        let halted = |o: &Observed| o.outputs.halt;
        let stretch = (2..t.len() - 1)
            .find(|&k| {
                halted(&t[k - 1]) && halted(&t[k]) && halted(&t[k + 1]) && !t[k].vector.reset
            })
            .expect("a halted stretch");
        match self {
            Breakage::IrqFlipped => t[stretch].outputs.irq ^= true,
            Breakage::EnableWhileHalted => t[stretch].outputs.drive_enable = 1,
            Breakage::EstopLate => {
                let edges = ESTOP_LATENCY as usize;
                let k = (0..t.len() - edges)
                    .find(|&k| !t[k].vector.inputs.estop_ok && !t[k].outputs.halt)
                    .expect("an e-stop while running");
                t[k + edges - 1].outputs.halt = false;
            }
            Breakage::HaltGlitch => t[stretch].outputs.halt = false,
            Breakage::BiteLate => {
                let watchdog = regmap::safety_io(AXES as u32)
                    .register("CAUSE")
                    .field("WATCHDOG")
                    .mask();
                // Every bite: the property checks only those left alone.
                let bit = |o: &Observed| o.registers.cause & watchdog != 0;
                let bites: Vec<usize> = (1..t.len())
                    .filter(|&k| bit(&t[k]) && !bit(&t[k - 1]))
                    .collect();
                assert!(!bites.is_empty(), "a bite");
                bites
                    .into_iter()
                    .for_each(|k| t[k].registers.cause &= !watchdog);
            }
            Breakage::LevelFromNothing => {
                // Axis 0's LIMIT_POS level flipped for the rest of the run.
                let k = t.len() / 2;
                t[k..].iter_mut().for_each(|o| o.registers.levels[0] ^= 1);
            }
            Breakage::LevelStuck => {
                // A level that never follows its pin: held at 0.
                t.iter_mut().for_each(|o| o.registers.levels[1] &= !1);
            }
            Breakage::CauseWhileDisabled => {
                let rose = |t: &[Observed], k: usize| {
                    t[k].registers.limit_cause & !t[k - 1].registers.limit_cause & 0xffff != 0
                };
                let k = (2..t.len())
                    .find(|&k| rose(&t, k) && !t[k].vector.reset && !t[k - 1].vector.reset)
                    .expect("a limit cause rising");
                t[k - 1].registers.input_ctrl[0] &= !0xffff;
            }
            Breakage::OutputNotSafe => {
                let k = (2..t.len())
                    .find(|&k| {
                        halted(&t[k - 1])
                            && halted(&t[k])
                            && t[k - 2..=k].iter().all(|o| !o.vector.reset)
                    })
                    .expect("a checked halted clock");
                t[k].outputs.gpo.oe ^= 1;
            }
            Breakage::GpiCauseUnselected => {
                let k = (2..t.len())
                    .find(|&k| {
                        t[k].registers.gpio[2] & !t[k - 1].registers.gpio[2] != 0
                            && t[k - 2..=k].iter().all(|o| !o.vector.reset)
                    })
                    .expect("a GPI cause rising");
                t[k - 1].registers.gpio[1] = 0;
            }
        }
        t
    }
}
