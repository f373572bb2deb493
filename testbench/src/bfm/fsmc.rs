//! The STM32F4 FSMC bus-functional model (mode 1): every 16- or 32-bit
//! access as the mode-1 waveform (ADDSET HCLKs of address phase, DATAST
//! HCLKs of strobe, a write's one HCLK of hold, NE1# low across the two
//! halves of a 32-bit access) at HCLK = 168 MHz against the 50 MHz FPGA
//! clock, on an exact time grid of 1/42 ns on which both clocks fall.
//!
//! [`timeline`] is the model; rust-hdl checks step through its events, and
//! [`stream`] hands the same events to the generic [`crate::player`] for
//! Icarus and Verilator.

use crate::player::{ClockSpec, PinStream};
use motionhdl_model::fsmc_bridge::{self as m, FsmcPins, FsmcTiming};

/// Time unit of the bus-functional models: 1/42 ns, so that the 20 ns FPGA
/// period (840) and the 168 MHz HCLK period (250) are both whole.
pub const TICKS_PER_NS: u64 = 42;
/// FPGA clock (50 MHz) and MCU clock (HCLK, 168 MHz) the checks run at.
pub const FPGA_CLOCK_HZ: u64 = 50_000_000;
pub const HCLK_HZ: u64 = 168_000_000;
/// FPGA clock period in ticks.
pub const CLOCK_TICKS: u64 = 840;
/// First rising FPGA edge (10 ns); edges follow every [`CLOCK_TICKS`].
pub const FIRST_EDGE_TICKS: u64 = 420;
/// HCLK period in ticks (5.952 ns).
pub const HCLK_TICKS: u64 = 250;
/// Distinct phases of the HCLK grid against the FPGA clock: HCLK edges sit
/// on multiples of gcd(250, 840) = 10 ticks (0.238 ns) from any FPGA edge,
/// 84 of them per period. The bus-functional model puts its grid 5 ticks
/// off those, so no bus event ever shares a time with an FPGA edge.
pub const PHASES: u32 = (CLOCK_TICKS / 10) as u32;
/// Grid offset of the MCU's events from the phase points.
const GRID: u64 = 5;
/// The write data is driven this long after NWE# falls (4 ns, pessimistic:
/// the FSMC drives it for the whole data phase).
pub const WRITE_DATA_DELAY_TICKS: u64 = 168;
/// The "end" read observation: 10 ticks (0.24 ns) before NOE# rises.
pub const END_OBSERVATION_TICKS: u64 = 10;
/// What the FPGA sees on D when the MCU does not drive it.
pub const FLOATING_BUS: u16 = 0xffff;
/// The timing the checks use: exactly [`m::stm32f4_timing`] at 50/168 MHz.
pub fn documented_timing() -> FsmcTiming {
    m::stm32f4_timing(FPGA_CLOCK_HZ, HCLK_HZ)
}

/// How long before NOE# rises the bridge's `d_out` must already be valid
/// in the (zero-delay) simulation: the read lead of the timing budget
/// (input skew + output delay + MCU setup), rounded up to the 10-tick grid.
pub fn read_lead_ticks() -> u64 {
    let b = m::stm32f4_budget(FPGA_CLOCK_HZ, HCLK_HZ);
    let ticks = (b.read_lead_ns * TICKS_PER_NS as f64).ceil() as u64;
    ticks.div_ceil(10) * 10
}

/// One step of stimulus. Addresses are FSMC halfword addresses A[11:0].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// One 16-bit read (an LDRH).
    Read16 { a: u16 },
    /// One 16-bit write (an STRH).
    Write16 { a: u16, data: u16 },
    /// A 32-bit read (an LDR at even `a`): two accesses, NE1# low across.
    Read32 { a: u16 },
    /// A 32-bit write (an STR at even `a`).
    Write32 { a: u16, data: u32 },
    /// A 16-bit access to another bank: the strobes move, NE1# stays high.
    Other { write: bool, a: u16, data: u16 },
    /// NE1# high for this many more HCLKs.
    Idle { hclk: u16 },
    /// Wait for the next FPGA rising edge, then put the HCLK grid at phase
    /// point `phase` (0..84) after it.
    Align { phase: u16 },
    /// Synchronous reset for 5 clocks, starting at the first falling edge
    /// 4 clocks after the last access (the slave keeps its contents).
    Reset,
}

/// What one read observed (at the MCU's pins as the bridge drives them):
/// `d_oe`/`d_out` the read lead before NOE# rises and just before it rises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Observation {
    pub oe_setup: bool,
    pub oe_end: bool,
    pub data_setup: u16,
    pub data_end: u16,
}

/// A pin change at a time, or an observation point.
#[derive(Clone, Copy, Debug)]
pub enum Event {
    /// The pins and the reset input from now on.
    Pins(FsmcPins, bool),
    /// Sample `d_oe`/`d_out` the read lead before NOE# rises.
    ObserveSetup,
    /// Sample them again just before NOE# rises.
    ObserveEnd,
}

fn next_rising(t: u64) -> u64 {
    if t < FIRST_EDGE_TICKS {
        FIRST_EDGE_TICKS
    } else {
        FIRST_EDGE_TICKS + ((t - FIRST_EDGE_TICKS) / CLOCK_TICKS + 1) * CLOCK_TICKS
    }
}

fn next_falling(t: u64) -> u64 {
    (t / CLOCK_TICKS + 1) * CLOCK_TICKS
}

/// The STM32F4 bus-functional model: every op as timed pin changes
/// (ticks). Returns the events and the end time.
pub fn timeline(ops: &[Op], timing: &FsmcTiming) -> (Vec<(u64, Event)>, u64) {
    let h = HCLK_TICKS;
    let lead = read_lead_ticks();
    let mut pins = FsmcPins::idle();
    pins.d_in = FLOATING_BUS;
    let mut reset = false;
    let mut t: u64 = GRID;
    let mut ev: Vec<(u64, Event)> = vec![(0, Event::Pins(pins, reset))];
    for op in ops {
        let (ours, write, accesses): (bool, bool, Vec<(u16, u16)>) = match *op {
            Op::Read16 { a } => (true, false, vec![(a, 0)]),
            Op::Write16 { a, data } => (true, true, vec![(a, data)]),
            Op::Read32 { a } => (true, false, vec![(a, 0), (a + 1, 0)]),
            Op::Write32 { a, data } => (
                true,
                true,
                vec![(a, data as u16), (a + 1, (data >> 16) as u16)],
            ),
            Op::Other { write, a, data } => (false, write, vec![(a, data)]),
            Op::Idle { hclk } => {
                t += u64::from(hclk) * h;
                continue;
            }
            Op::Align { phase } => {
                assert!(u32::from(phase) < PHASES);
                t = next_rising(t) + GRID + 10 * u64::from(phase);
                continue;
            }
            Op::Reset => {
                // Four clocks after the last access: its action is done.
                t = next_falling(t + 4 * CLOCK_TICKS);
                reset = true;
                ev.push((t, Event::Pins(pins, reset)));
                t += 5 * CLOCK_TICKS;
                reset = false;
                ev.push((t, Event::Pins(pins, reset)));
                t += GRID;
                continue;
            }
        };
        assert!(timing.datast >= 1 && u64::from(timing.datast) * h > lead + END_OBSERVATION_TICKS);
        pins.ne_n = !ours;
        for (a, data) in accesses {
            // Address phase: A (and, for a write, not yet the data).
            pins.a = a & 0xfff;
            if write {
                pins.d_in = !data;
            }
            ev.push((t, Event::Pins(pins, reset)));
            let fall = t + u64::from(timing.addset) * h;
            let rise = fall + u64::from(timing.datast) * h;
            if write {
                pins.nwe_n = false;
                ev.push((fall, Event::Pins(pins, reset)));
                pins.d_in = data;
                ev.push((fall + WRITE_DATA_DELAY_TICKS, Event::Pins(pins, reset)));
                pins.nwe_n = true;
                ev.push((rise, Event::Pins(pins, reset)));
                // One HCLK of hold with NWE# high, then the next access.
                t = rise + h;
            } else {
                pins.noe_n = false;
                ev.push((fall, Event::Pins(pins, reset)));
                ev.push((rise - lead, Event::ObserveSetup));
                ev.push((rise - END_OBSERVATION_TICKS, Event::ObserveEnd));
                pins.noe_n = true;
                ev.push((rise, Event::Pins(pins, reset)));
                t = rise;
            }
        }
        pins.ne_n = true;
        pins.d_in = FLOATING_BUS;
        ev.push((t, Event::Pins(pins, reset)));
        t += (1 + u64::from(timing.busturn)) * h;
    }
    // Events at one time stay in push order.
    ev.sort_by_key(|e| e.0);
    (ev, t + 8 * CLOCK_TICKS)
}

/// The pins [`stream`] drives, as the bridge names them.
pub const PINS: [&str; 6] = ["reset", "ne_n", "noe_n", "nwe_n", "a", "d_in"];

fn pin_values(p: &FsmcPins, reset: bool) -> Vec<u64> {
    vec![
        u64::from(reset),
        u64::from(p.ne_n),
        u64::from(p.noe_n),
        u64::from(p.nwe_n),
        u64::from(p.a),
        u64::from(p.d_in),
    ]
}

/// The FPGA clock of the time grid, for the player.
pub const CLOCK: ClockSpec = ClockSpec {
    period: CLOCK_TICKS,
    ticks_per_ns: TICKS_PER_NS,
};

/// [`timeline`] as a pin stream over [`PINS`]: one sample row at each
/// observation point (setup, then end, per read).
pub fn stream(ops: &[Op], timing: &FsmcTiming) -> PinStream {
    let (events, end) = timeline(ops, timing);
    PinStream::from_events(&PINS, &events, end, |e| match e {
        Event::Pins(p, reset) => Some(pin_values(p, *reset)),
        Event::ObserveSetup | Event::ObserveEnd => None,
    })
}

/// The reads of a played [`stream`], from samples whose first two values
/// are `d_oe` and `d_out`: pairs of (setup, end) rows. An undriven bus
/// (X) reads as not driven.
pub fn observations(samples: &[Vec<Option<u64>>]) -> Result<Vec<Observation>, String> {
    if !samples.len().is_multiple_of(2) {
        return Err(format!(
            "{} samples: not pairs of setup and end",
            samples.len()
        ));
    }
    let read = |s: &[Option<u64>]| -> Result<(bool, u16), String> {
        match s {
            [Some(oe), data, ..] => Ok((*oe == 1, data.unwrap_or(0) as u16)),
            _ => Err(format!("unreadable sample {s:?}")),
        }
    };
    samples
        .chunks(2)
        .map(|pair| {
            let (oe_setup, data_setup) = read(&pair[0])?;
            let (oe_end, data_end) = read(&pair[1])?;
            Ok(Observation {
                oe_setup,
                oe_end,
                data_setup,
                data_end,
            })
        })
        .collect()
}
