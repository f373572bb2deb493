//! The serial option's contract (SERIAL.MODE = 1), stated from the bus
//! and the SCLK, SDIN, SYNC and LOADDACS pins alone: each frame's timing
//! against the transfer's own SERIAL and TIMING values (so every setting
//! a run writes is checked), and each transfer's four frames against the
//! PREFIX and codes staged before it started.

use super::{counted, property_reports, staged, Observed, Staged};
use crate::harness::CheckReport;
use motionhdl_model::servo_dac::{DAC_CHANNELS, FRAME_BITS, SAFE_CODE};

const CH: usize = DAC_CHANNELS as usize;

/// The serial properties, in the order [`contract`] reports them.
pub const PROPERTIES: [&str; 3] = [
    "SYNC is low only while CS and LOADDACS are high",
    "every frame keeps its transfer's SERIAL and TIMING: SYNC falls and rises with SCLK \
     high, 24 SCLK falls, every SCLK high and low and SYNC's fall to the first fall and \
     the last fall to SYNC's rise at least SCLK_HALF + 1 clocks, SDIN changing only as \
     SCLK rises, SYNC high at least SYNC_HIGH + 1 clocks before each frame and before \
     LOADDACS falls, LOADDACS low at least LDAC_LOW + 1 clocks",
    "between two LOADDACS rises of a serial transfer, four frames carry PREFIX.CH0..CH3 \
     and the codes staged before the transfer started (SAFE_CODE while safe)",
];

/// One frame: the clocks SYNC is low (`from..=to`) and the bits sampled
/// at SCLK's falls.
#[derive(Clone, Debug)]
pub struct Frame {
    pub from: usize,
    pub to: usize,
    pub bits: Vec<bool>,
}

impl Frame {
    /// The 24 bits as a word, MSB first.
    pub fn word(&self) -> u32 {
        self.bits.iter().fold(0, |w, &b| w << 1 | u32::from(b))
    }
}

/// Every serial property over `trace`: one report each.
pub fn contract(trace: &[Observed]) -> Vec<CheckReport> {
    let mut r = property_reports(&PROPERTIES);
    let pins = |k: usize| trace[k].outputs.pins;
    for k in 0..trace.len() {
        if !pins(k).sync_n {
            r[0].case(
                (!pins(k).cs_n || !pins(k).ldac_n)
                    .then(|| format!("clock {k}: SYNC low with CS or LOADDACS low")),
            );
        }
    }
    transfers(trace, &staged(trace), &mut r);
    counted(r)
}

/// The edge that started the transfer whose first SYNC fall is clock `k`:
/// the setup lasts SYNC_HIGH + 1 clocks of the value staged before it.
fn start_of(staged: &[Staged], k: usize) -> Option<usize> {
    (k.saturating_sub(257).max(1)..k)
        .rev()
        .find(|&s| staged[s - 1].serial.2 + 1 == (k - s) as u32)
}

/// Properties 1 and 2, transfer by transfer.
fn transfers(trace: &[Observed], staged: &[Staged], r: &mut [CheckReport]) {
    let pins = |k: usize| trace[k].outputs.pins;
    let mut frames: Vec<Frame> = Vec::new();
    // The running transfer's start and what it must carry.
    let mut start: Option<usize> = None;
    let mut last_sync_rise = 0;
    let mut k = 1;
    while k < trace.len() {
        if trace[k].vector.reset {
            (frames, start) = (Vec::new(), None);
        } else if pins(k - 1).sync_n && !pins(k).sync_n {
            let Some(to) = (k..trace.len()).find(|&j| pins(j).sync_n).map(|j| j - 1) else {
                break;
            };
            if trace[k..=(to + 1).min(trace.len() - 1)]
                .iter()
                .any(|o| o.vector.reset)
            {
                // Cut short by a reset: the next loop turn clears up.
                k = to + 1;
                continue;
            }
            if frames.is_empty() {
                start = start_of(staged, k);
            }
            let frame = frame_at(trace, k, to);
            if let Some(s) = start {
                let (_, half, sync_high) = staged[s - 1].serial;
                let gap = k - last_sync_rise;
                let gap_ok = frames.is_empty() || gap as u32 > sync_high;
                r[1].case(
                    frame_timing(trace, &frame, half)
                        .or_else(|| (!gap_ok).then(|| format!("SYNC high {gap} clocks")))
                        .map(|e| format!("frame at clocks {k}..={to}: {e}")),
                );
            }
            frames.push(frame);
            last_sync_rise = to + 1;
            k = to + 1;
            continue;
        } else if !pins(k - 1).ldac_n && pins(k).ldac_n && !frames.is_empty() {
            check_load(trace, staged, (start, last_sync_rise, k), &frames, r);
            (frames, start) = (Vec::new(), None);
        }
        k += 1;
    }
}

/// The frame SYNC frames in clocks `from..=to`, sampled at SCLK's falls.
fn frame_at(trace: &[Observed], from: usize, to: usize) -> Frame {
    let pins = |k: usize| trace[k].outputs.pins;
    let bits = (from + 1..=to)
        .filter(|&j| pins(j - 1).sclk && !pins(j).sclk)
        .map(|j| pins(j).sdin)
        .collect();
    Frame { from, to, bits }
}

/// What is wrong with `frame`'s timing for SCLK_HALF = `half`, if anything.
fn frame_timing(trace: &[Observed], frame: &Frame, half: u32) -> Option<String> {
    let pins = |k: usize| trace[k].outputs.pins;
    let (from, to) = (frame.from, frame.to);
    if !pins(from).sclk || !pins(to).sclk {
        return Some("SCLK low as SYNC falls or rises".into());
    }
    if frame.bits.len() != FRAME_BITS as usize {
        return Some(format!("{} SCLK falls", frame.bits.len()));
    }
    // SCLK's runs inside the frame; the last (high after the last rise)
    // is measured to SYNC's rise together with the low before it.
    let mut runs = vec![1usize];
    for j in from + 1..=to {
        if pins(j).sclk == pins(j - 1).sclk {
            *runs.last_mut().unwrap() += 1;
        } else {
            runs.push(1);
        }
    }
    let last = runs.pop().unwrap() + runs.pop().unwrap_or(0);
    let min = half as usize + 1;
    if runs.iter().any(|&n| n < min) || last < min + 1 {
        return Some(format!("SCLK runs {runs:?} then {last}, want >= {min}"));
    }
    let rose = |j: usize| !pins(j - 1).sclk && pins(j).sclk;
    let moved = (from + 1..=to).find(|&j| pins(j).sdin != pins(j - 1).sdin && !rose(j));
    moved.map(|j| format!("SDIN changes at clock {j} without an SCLK rise"))
}

/// Property 3 at a LOADDACS rise at clock `rise`, and property 2's
/// LOADDACS timing: `at` = (the transfer's start, the last SYNC rise, the
/// LOADDACS rise).
fn check_load(
    trace: &[Observed],
    staged: &[Staged],
    (start, sync_rise, rise): (Option<usize>, usize, usize),
    frames: &[Frame],
    r: &mut [CheckReport],
) {
    let fall = (sync_rise..rise)
        .find(|&j| !trace[j].outputs.pins.ldac_n)
        .unwrap_or(rise);
    let Some(s) = start else {
        r[2].case(Some(format!(
            "LOADDACS rise at {rise}: no transfer start found"
        )));
        return;
    };
    let st = staged[s - 1];
    let want_codes = if trace[s].vector.safe {
        [SAFE_CODE; CH]
    } else {
        st.codes
    };
    let want: Vec<u32> = (0..CH)
        .map(|c| (st.prefix >> (8 * c) & 0xff) << 16 | want_codes[c])
        .collect();
    let got: Vec<u32> = frames.iter().map(Frame::word).collect();
    r[2].case((got != want).then(|| {
        format!("LOADDACS rise at {rise} (start {s}): frames {got:06x?}, want {want:06x?}")
    }));
    let (gap, low) = ((fall - sync_rise) as u32, (rise - fall) as u32);
    r[1].case(
        (gap <= st.serial.2 || low <= st.ldac_low).then(|| {
            format!("LOADDACS at {fall}..{rise}: {gap} clocks after SYNC rose, low {low}")
        }),
    );
}

/// A deliberate fault put into a trace, to show a serial property can
/// fail.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Breakage {
    /// SYNC low in a clock where LOADDACS is low.
    SyncDuringLoad,
    /// SDIN changes in a clock where SCLK falls.
    DataMovesAtFall,
    /// One frame bit inverted for the whole of its SCLK cycle.
    WrongBit,
}

impl Breakage {
    pub const ALL: [Breakage; 3] = [
        Breakage::SyncDuringLoad,
        Breakage::DataMovesAtFall,
        Breakage::WrongBit,
    ];

    /// The property this breakage must make fail (an index into
    /// [`PROPERTIES`]).
    pub fn property(self) -> usize {
        match self {
            Breakage::SyncDuringLoad => 0,
            Breakage::DataMovesAtFall => 1,
            Breakage::WrongBit => 2,
        }
    }

    /// `trace` with this fault put in once, somewhere past `from`.
    pub fn apply(self, trace: &[Observed], from: usize) -> Vec<Observed> {
        let mut t = trace.to_vec();
        let p = |t: &[Observed], k: usize| t[k].outputs.pins;
        let fall = |t: &[Observed], k: usize| !p(t, k).sync_n && p(t, k - 1).sclk && !p(t, k).sclk;
        let k = (from.max(1)..t.len() - 1)
            .find(|&k| match self {
                Breakage::SyncDuringLoad => !p(&t, k).ldac_n && p(&t, k - 1).sync_n,
                Breakage::DataMovesAtFall | Breakage::WrongBit => fall(&t, k),
            })
            .expect("the trace has the event to break");
        match self {
            Breakage::SyncDuringLoad => t[k].outputs.pins.sync_n = false,
            Breakage::DataMovesAtFall => t[k].outputs.pins.sdin ^= true,
            Breakage::WrongBit => {
                // From the rise before the fall to the rise after it.
                let mut j = k;
                while p(&t, j - 1).sclk != p(&t, j).sclk || !p(&t, j).sclk {
                    j -= 1;
                }
                while j < t.len() && (j <= k || !p(&t, j).sclk) {
                    t[j].outputs.pins.sdin ^= true;
                    j += 1;
                }
            }
        }
        t
    }
}
