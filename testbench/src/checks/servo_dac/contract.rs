//! The servo DAC block's contract, stated from its bus and its DAC pins
//! alone (never from the model), checked over runs of the HDL. Each
//! property counts the clocks where its antecedent held, and [`Breakage`]
//! shows each one able to fail.

use super::{
    counted, property_reports, run_rust, staged, update_latency_of, Observed, Vector, CLOCK_HZ,
};
use crate::harness::{CheckReport, Rng};
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap;
use motionhdl_model::servo_dac::{DAC_CHANNELS, SAFE_CODE};

const CH: usize = DAC_CHANNELS as usize;

/// The properties, in the order [`contract`] reports them.
pub const PROPERTIES: [&str; 4] = [
    "R/W is low at every clock",
    "CS and LOADDACS are never low together",
    "address and data hold from the clock before CS falls to the clock after it rises",
    "between two LOADDACS rises channels 0..3 are written once each, in order, each with \
     the code staged before its transfer started (SAFE_CODE while safe)",
];

/// The zero-jitter property of [`zero_jitter`].
pub const ZERO_JITTER: &str =
    "every tick that finds the interface idle is followed by LOADDACS rising exactly \
     update_latency(TIMING) edges later (serial_update_latency(SERIAL, TIMING) with \
     SERIAL.MODE = 1), and by no other rise";

/// Every property over `trace`: one report each, a case per antecedent.
pub fn contract(trace: &[Observed]) -> Vec<CheckReport> {
    let mut r = property_reports(&PROPERTIES);
    let pins = |k: usize| trace[k].outputs.pins;
    let reset_in = |a: usize, b: usize| trace[a..=b].iter().any(|o| o.vector.reset);
    for k in 0..trace.len() {
        r[0].case(pins(k).rw_n.then(|| format!("clock {k}: R/W high")));
        if !pins(k).ldac_n || !pins(k).cs_n {
            r[1].case(
                (!pins(k).ldac_n && !pins(k).cs_n)
                    .then(|| format!("clock {k}: CS and LOADDACS both low")),
            );
        }
    }
    for k in 1..trace.len().saturating_sub(1) {
        if pins(k).cs_n || reset_in(k - 1, k + 1) {
            continue;
        }
        let held = [k - 1, k + 1]
            .iter()
            .all(|&j| (pins(j).data, pins(j).addr) == (pins(k).data, pins(k).addr));
        r[2].case((!held).then(|| {
            format!(
                "clock {k}: CS low, address/data {:?} {:?} {:?}",
                pins(k - 1),
                pins(k),
                pins(k + 1)
            )
        }));
    }
    transfers(trace, &mut r[3]);
    counted(r)
}

/// Property 3: each LOADDACS rise ends a transfer of four writes in
/// channel order carrying the codes staged before the transfer's start
/// (the edge before the first write's setup clock).
fn transfers(trace: &[Observed], r: &mut CheckReport) {
    let codes: Vec<[u32; CH]> = staged(trace).iter().map(|s| s.codes).collect();
    let pins = |k: usize| trace[k].outputs.pins;
    // (channel, data) of each write since the last LOADDACS rise, and
    // the codes the running transfer must carry.
    let mut writes: Vec<(u32, u32)> = Vec::new();
    let mut want: Option<[u32; CH]> = None;
    // A serial transfer's rise is the serial contract's.
    let mut framed = false;
    for k in 3..trace.len() {
        if trace[k].vector.reset {
            writes.clear();
            want = None;
            framed = false;
            continue;
        }
        framed |= !pins(k).sync_n;
        let cs_fell = pins(k - 1).cs_n && !pins(k).cs_n;
        if cs_fell {
            if writes.is_empty() {
                // The start edge is k - 1 (the setup clock follows it):
                // the codes written up to edge k - 2, or SAFE_CODE if the
                // safe input was high at the start edge.
                let start = k - 1;
                want = Some(if trace[start].vector.safe {
                    [SAFE_CODE; CH]
                } else {
                    codes[start - 1]
                });
            }
            writes.push((pins(k).addr, pins(k).data));
        }
        if !pins(k - 1).ldac_n && pins(k).ldac_n && framed && writes.is_empty() {
            framed = false;
        } else if !pins(k - 1).ldac_n && pins(k).ldac_n {
            framed = false;
            let order: Vec<u32> = writes.iter().map(|w| w.0).collect();
            let data: Vec<u32> = writes.iter().map(|w| w.1).collect();
            let ok = order == [0, 1, 2, 3] && want.is_some_and(|w| data[..] == w[..]);
            r.case((!ok).then(|| {
                format!("LOADDACS rise at clock {k}: writes {writes:x?}, staged {want:x?}")
            }));
            writes.clear();
            want = None;
        }
    }
}

/// Clocks from a transfer's start to its LOADDACS rise with TIMING and
/// SERIAL at their reset values, on the parallel pins or (`serial`) SPI.
pub fn reset_latency(serial: bool) -> usize {
    let map = regmap::servo_dac(CLOCK_HZ);
    let spi = map.register("SERIAL").reset | u32::from(serial);
    update_latency_of(&map, map.register("TIMING").reset, spi) as usize
}

/// A servo loop as firmware runs one: TIMING and SERIAL at their reset
/// values (SERIAL.MODE = 1 with `serial`), the tick at a period longer
/// than a transfer, new codes written at random clocks of each period;
/// `ticks` periods.
pub fn servo_run(ticks: usize, serial: bool) -> Vec<Observed> {
    let map = regmap::servo_dac(CLOCK_HZ);
    let ch = map.array("CH");
    let period = reset_latency(serial) + 7;
    let mut next = Rng::stream(0xdac0_0007);
    let mut v = vec![
        Vector {
            reset: true,
            ..Default::default()
        };
        2
    ];
    let spi = map.register("SERIAL");
    v.push(Vector {
        bus: BusCycle::write(spi.offset, spi.reset | u32::from(serial)),
        ..Default::default()
    });
    v.push(Vector {
        bus: BusCycle::write(map.register("TICK_PERIOD").offset, period as u32),
        ..Default::default()
    });
    while v.len() < 4 + ticks * period {
        let bus = if next().is_multiple_of(4) {
            let c = (next() % CH as u64) as u32;
            BusCycle::write(ch.address(c, "CODE"), next() as u32)
        } else {
            BusCycle::default()
        };
        v.push(Vector {
            bus,
            ..Default::default()
        });
    }
    run_rust(&v)
}

/// The zero-jitter property over a run without UPDATE writes, safe
/// changes or TIMING writes (TIMING and SERIAL's times at their reset
/// values, SERIAL.MODE = `serial`).
pub fn zero_jitter(trace: &[Observed], serial: bool) -> CheckReport {
    let latency = reset_latency(serial);
    let mut r = CheckReport::new("servo_dac", ZERO_JITTER, 0);
    let rises: Vec<usize> = (1..trace.len())
        .filter(|&k| !trace[k - 1].outputs.pins.ldac_n && trace[k].outputs.pins.ldac_n)
        .collect();
    let mut busy_until = 0;
    for t in (0..trace.len()).filter(|&t| trace[t].outputs.tick) {
        // The transfer starts at the edge after the tick's clock.
        let start = t + 1;
        if start < busy_until || start + latency >= trace.len() {
            continue;
        }
        busy_until = start + latency;
        let after: Vec<usize> = rises
            .iter()
            .copied()
            .filter(|&k| k > start && k <= start + latency)
            .collect();
        r.case((after != [start + latency]).then(|| {
            format!(
                "tick at clock {t}: LOADDACS rises at {after:?}, want {}",
                start + latency
            )
        }));
    }
    r.expected = r.covered;
    r
}

/// A deliberate fault put into a trace, to show a property can fail.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Breakage {
    /// R/W high for one clock.
    ReadCycle,
    /// LOADDACS low in a clock where CS is low.
    LoadDuringWrite,
    /// The data change in the last clock of a CS low.
    DataChangesUnderCs,
    /// Channel 1's write addressed to channel 2.
    WrongChannel,
    /// LOADDACS rises one clock late after some tick.
    LateLoad,
}

impl Breakage {
    pub const ALL: [Breakage; 5] = [
        Breakage::ReadCycle,
        Breakage::LoadDuringWrite,
        Breakage::DataChangesUnderCs,
        Breakage::WrongChannel,
        Breakage::LateLoad,
    ];

    /// The property this breakage must make fail (an index into
    /// [`PROPERTIES`], or `None` for [`ZERO_JITTER`]).
    pub fn property(self) -> Option<usize> {
        match self {
            Breakage::ReadCycle => Some(0),
            Breakage::LoadDuringWrite => Some(1),
            Breakage::DataChangesUnderCs => Some(2),
            Breakage::WrongChannel => Some(3),
            Breakage::LateLoad => None,
        }
    }

    /// `trace` with this fault put in once, somewhere past `from`.
    pub fn apply(self, trace: &[Observed], from: usize) -> Vec<Observed> {
        let mut t = trace.to_vec();
        let cs_low = |t: &[Observed], k: usize| !t[k].outputs.pins.cs_n;
        let k = (from..t.len() - 1)
            .find(|&k| match self {
                Breakage::ReadCycle => true,
                Breakage::LoadDuringWrite | Breakage::DataChangesUnderCs => {
                    cs_low(&t, k) && !cs_low(&t, k + 1)
                }
                Breakage::WrongChannel => cs_low(&t, k) && t[k].outputs.pins.addr == 1,
                Breakage::LateLoad => !t[k].outputs.pins.ldac_n && t[k + 1].outputs.pins.ldac_n,
            })
            .expect("the trace has the event to break");
        match self {
            Breakage::ReadCycle => t[k].outputs.pins.rw_n = true,
            Breakage::LoadDuringWrite => t[k].outputs.pins.ldac_n = false,
            Breakage::DataChangesUnderCs => t[k].outputs.pins.data ^= 1,
            Breakage::WrongChannel => {
                // The whole write, so the hold property still holds.
                let mut j = k;
                while cs_low(&t, j) {
                    j -= 1;
                }
                for o in &mut t[j..=k + 1] {
                    o.outputs.pins.addr = 2;
                }
            }
            Breakage::LateLoad => t[k + 1].outputs.pins.ldac_n = false,
        }
        t
    }
}
