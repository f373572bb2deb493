//! The ISA bus-functional model: every I/O cycle as pin changes at real
//! times (8.33 MHz bus, BALE, AEN, IOR#/IOW# of a chosen length) against
//! the 50 MHz FPGA clock, and the DSP port's one-clock reads and writes.
//! Times are in ps.
//!
//! [`timeline`] is the model; rust-hdl checks step through its events, and
//! [`stream`] hands the same events to the generic [`crate::player`] for
//! Icarus and Verilator.

use crate::player::{ClockSpec, PinStream};
use motionhdl_model::isa_bridge::IsaPins;

/// FPGA clock period (50 MHz).
pub const CLOCK_PS: u64 = 20_000;
/// First rising clock edge; edges follow every [`CLOCK_PS`].
pub const FIRST_EDGE_PS: u64 = 10_000;
/// ISA bus clock period (8.33 MHz).
pub const BCLK_NS: u64 = 120;
/// BALE high time at the start of a cycle (half a BCLK).
pub const BALE_NS: u64 = 60;
/// Command starts one BCLK after the cycle (BALE rising).
pub const COMMAND_DELAY_NS: u64 = BCLK_NS;
/// The bus drives write data this long after IOW# falls (pessimistic).
pub const WRITE_DATA_DELAY_NS: u64 = 15;
/// Write data held after IOW# rises.
pub const WRITE_DATA_HOLD_NS: u64 = 25;
/// SA and AEN held after the command ends, before the next cycle.
pub const ADDRESS_HOLD_NS: u64 = 60;
/// The host needs read data this long before IOR# rises.
pub const READ_SETUP_NS: u64 = 20;
/// Command (IOR#/IOW# low) lengths the checks cover: from 110 ns, shorter
/// than a 16-bit I/O cycle without wait states on an 8.33 MHz bus, to
/// 600 ns, an 8-bit-style cycle with four wait states.
pub const COMMAND_NS: [u64; 5] = [110, 180, 240, 360, 600];
/// Command length of the set-up and read-back cycles around a case.
pub const STANDARD_COMMAND_NS: u64 = 240;
/// Half a nanosecond: bus events sit this far off the clock edges.
pub const HALF_NS: u64 = 500;
/// What the PC sees on undriven SD lines.
pub const FLOATING_BUS: u16 = 0xffff;

/// One step of stimulus.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// An ISA I/O write (OUT) cycle.
    IoWrite {
        port: u16,
        aen: bool,
        data: u16,
        command_ns: u64,
    },
    /// An ISA I/O read (IN) cycle.
    IoRead {
        port: u16,
        aen: bool,
        command_ns: u64,
    },
    /// The DSP writes one word (one clock, set up at a falling edge).
    DspWrite { addr: u16, data: u16 },
    /// The DSP reads one word; the data is taken one clock later.
    DspRead { addr: u16 },
    /// Wait for the next rising edge, then `offset_ps` more: sets the phase
    /// of whatever follows against the FPGA clock.
    Align { offset_ps: u64 },
    /// Synchronous reset for 5 clocks (the RAM keeps its contents).
    Reset,
}

/// What a read observes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Observation {
    /// An I/O read: SD drive and data [`READ_SETUP_NS`] before IOR# rises
    /// and 1 ns before it rises.
    Io {
        oe_setup: bool,
        oe_end: bool,
        data_setup: u16,
        data_end: u16,
    },
    /// A DSP read.
    Dsp { data: u16 },
}

/// A pin change at a time, or an observation point.
#[derive(Clone, Copy, Debug)]
pub enum Event {
    Pins(IsaPins, bool),
    ObserveIo { setup: bool },
    ObserveDsp,
}

fn next_rising(t: u64) -> u64 {
    if t < FIRST_EDGE_PS {
        FIRST_EDGE_PS
    } else {
        FIRST_EDGE_PS + ((t - FIRST_EDGE_PS) / CLOCK_PS + 1) * CLOCK_PS
    }
}

fn next_falling(t: u64) -> u64 {
    (t / CLOCK_PS + 1) * CLOCK_PS
}

/// The bus-functional model: every op as timed pin changes (ps). Returns the
/// events and the end time.
pub fn timeline(base: u8, ops: &[Op]) -> (Vec<(u64, Event)>, u64) {
    let mut pins = IsaPins::idle(base);
    pins.sd_in = FLOATING_BUS;
    let mut reset = false;
    // Bus events fall on whole nanoseconds plus half a nanosecond, clock
    // edges on whole nanoseconds: no event shares a time with an edge.
    let mut t: u64 = HALF_NS;
    let mut ev: Vec<(u64, Event)> = vec![(0, Event::Pins(pins, reset))];
    let ns = 1000;
    for op in ops {
        match *op {
            Op::IoWrite { .. } | Op::IoRead { .. } => {
                let (port, aen, command_ns, write, data) = match *op {
                    Op::IoWrite {
                        port,
                        aen,
                        data,
                        command_ns,
                    } => (port, aen, command_ns, true, data),
                    Op::IoRead {
                        port,
                        aen,
                        command_ns,
                    } => (port, aen, command_ns, false, 0),
                    _ => unreachable!(),
                };
                assert!(command_ns > READ_SETUP_NS.max(WRITE_DATA_DELAY_NS) + 1);
                pins.sa = port & 0x3ff;
                pins.aen = aen;
                pins.bale = true;
                ev.push((t, Event::Pins(pins, reset)));
                // BALE stays high through DMA cycles.
                pins.bale = aen;
                t += BALE_NS * ns;
                ev.push((t, Event::Pins(pins, reset)));
                t += (COMMAND_DELAY_NS - BALE_NS) * ns;
                if write {
                    pins.iow_n = false;
                    ev.push((t, Event::Pins(pins, reset)));
                    pins.sd_in = data;
                    ev.push((t + WRITE_DATA_DELAY_NS * ns, Event::Pins(pins, reset)));
                    t += command_ns * ns;
                    pins.iow_n = true;
                    ev.push((t, Event::Pins(pins, reset)));
                    pins.sd_in = FLOATING_BUS;
                    ev.push((t + WRITE_DATA_HOLD_NS * ns, Event::Pins(pins, reset)));
                } else {
                    pins.ior_n = false;
                    ev.push((t, Event::Pins(pins, reset)));
                    let rise = t + command_ns * ns;
                    ev.push((rise - READ_SETUP_NS * ns, Event::ObserveIo { setup: true }));
                    ev.push((rise - ns, Event::ObserveIo { setup: false }));
                    t = rise;
                    pins.ior_n = true;
                    ev.push((t, Event::Pins(pins, reset)));
                }
                t += ADDRESS_HOLD_NS * ns;
                pins.bale = false;
                ev.push((t, Event::Pins(pins, reset)));
            }
            Op::DspWrite { addr, data } => {
                t = next_falling(t);
                pins.dsp_addr = addr;
                pins.dsp_wdata = data;
                pins.dsp_we = true;
                ev.push((t, Event::Pins(pins, reset)));
                t = next_falling(t);
                pins.dsp_we = false;
                ev.push((t, Event::Pins(pins, reset)));
                t += HALF_NS;
            }
            Op::DspRead { addr } => {
                t = next_falling(t);
                pins.dsp_addr = addr;
                ev.push((t, Event::Pins(pins, reset)));
                t = next_falling(t);
                ev.push((t, Event::ObserveDsp));
                t += HALF_NS;
            }
            Op::Align { offset_ps } => {
                assert!(offset_ps < CLOCK_PS);
                t = next_rising(t) + offset_ps;
            }
            Op::Reset => {
                t = next_falling(t);
                reset = true;
                ev.push((t, Event::Pins(pins, reset)));
                t += 5 * CLOCK_PS;
                reset = false;
                ev.push((t, Event::Pins(pins, reset)));
                t += HALF_NS;
            }
        }
    }
    (ev, t + 4 * CLOCK_PS)
}

/// The pins [`stream`] drives, as the bridge names them (the DSP port's
/// pins belong to the external build's RAM chip).
pub const PINS: [&str; 11] = [
    "reset",
    "sa",
    "sd_in",
    "ior_n",
    "iow_n",
    "aen",
    "bale",
    "base",
    "dsp_addr",
    "dsp_wdata",
    "dsp_we",
];

/// `p` and `reset` as values in [`PINS`] order.
pub fn pin_values(p: &IsaPins, reset: bool) -> Vec<u64> {
    let b = |x: bool| u64::from(x);
    vec![
        b(reset),
        u64::from(p.sa),
        u64::from(p.sd_in),
        b(p.ior_n),
        b(p.iow_n),
        b(p.aen),
        b(p.bale),
        u64::from(p.base),
        u64::from(p.dsp_addr),
        u64::from(p.dsp_wdata),
        b(p.dsp_we),
    ]
}

/// The FPGA clock in ps, for the player.
pub const CLOCK: ClockSpec = ClockSpec {
    period: CLOCK_PS,
    ticks_per_ns: 1000,
};

/// Nets each sample row of [`stream`] needs, in the order
/// [`observations`] reads them.
pub const SAMPLED: [&str; 3] = ["sd_oe", "sd_out", "dsp_rdata"];

/// [`timeline`] as a pin stream over [`PINS`], with one sample row per
/// observation point, and those points' kinds in order.
pub fn stream(base: u8, ops: &[Op]) -> (PinStream, Vec<Event>) {
    let (events, end) = timeline(base, ops);
    let stream = PinStream::from_events(&PINS, &events, end, |e| match e {
        Event::Pins(p, reset) => Some(pin_values(p, *reset)),
        _ => None,
    });
    let points = events
        .iter()
        .map(|(_, e)| *e)
        .filter(|e| !matches!(e, Event::Pins(..)))
        .collect();
    (stream, points)
}

/// What the reads of a played [`stream`] observed, from the samples of
/// [`SAMPLED`] at `points`. Undriven data (X) is not compared, and reads
/// as 0.
pub fn observations(
    points: &[Event],
    samples: &[Vec<Option<u64>>],
) -> Result<Vec<Observation>, String> {
    if points.len() != samples.len() {
        return Err(format!(
            "{} samples for {} points",
            samples.len(),
            points.len()
        ));
    }
    let mut out = Vec::new();
    let mut setup = None;
    for (point, s) in points.iter().zip(samples) {
        let [oe, data, dsp] = s.as_slice() else {
            return Err(format!("unreadable sample {s:?}"));
        };
        let driven = |oe: &Option<u64>| match oe {
            Some(v) => Ok(*v == 1),
            None => Err(format!("sd_oe is X in {s:?}")),
        };
        let data_if = |on: bool| match (on, data) {
            (false, _) => Ok(0),
            (true, Some(v)) => Ok(*v as u16),
            (true, None) => Err(format!("driven sd_out is X in {s:?}")),
        };
        match point {
            Event::ObserveIo { setup: true } => {
                let on = driven(oe)?;
                setup = Some((on, data_if(on)?));
            }
            Event::ObserveIo { setup: false } => {
                let (oe_setup, data_setup) =
                    setup.take().ok_or("an end sample without its setup")?;
                let oe_end = driven(oe)?;
                out.push(Observation::Io {
                    oe_setup,
                    oe_end,
                    data_setup,
                    data_end: data_if(oe_end)?,
                });
            }
            Event::ObserveDsp => {
                let data = dsp.ok_or_else(|| format!("dsp_rdata is X in {s:?}"))?;
                out.push(Observation::Dsp { data: data as u16 });
            }
            Event::Pins(..) => unreachable!("pins are not sample points"),
        }
    }
    Ok(out)
}
