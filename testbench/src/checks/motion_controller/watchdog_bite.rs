//! The watchdog in the whole controller (docs/safety_io.md, "Watchdog"
//! and "General-purpose outputs"): firmware feeds it while two axes move,
//! then stops feeding it, as a crashed MCU would, and it bites: every axis
//! stops, the drives are disabled, the general-purpose outputs go to their
//! safe state, the IRQ pin falls, and the counters keep counting.

use super::limit_stop::creep;
use super::system::{two_axes, System, DRIVE_LATENCY};
use crate::trace::Trace;
use motionhdl_model::safety_io::WATCHDOG_KEY;
use motionhdl_model::Config;

/// The watchdog's timeout, clocks.
pub const TIMEOUT: u32 = 3_000;
/// Clocks between two feeds while firmware runs.
pub const FEED_EVERY: u64 = 1_000;
/// Feeds before firmware "crashes".
pub const FEEDS: u32 = 4;
/// The outputs' running value and safe state.
pub const RUNNING: u32 = 0x000f;
pub const SAFE: u32 = 0x00f0;
/// Outputs 4 and 0 open-drain: a safe 1 releases output 4's pin.
pub const OPEN_DRAIN: u32 = 0x0011;

/// What the run saw.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bite {
    /// Clock of the last feed, and the first clock with HALT seen at the
    /// drive ENABLE pins (0).
    pub last_feed: u64,
    pub disabled_at: u64,
    /// Shaft positions once the steps on their way at the bite have
    /// arrived, and after idling on.
    pub at_bite: Vec<i32>,
    pub later: Vec<i32>,
}

/// On a set-up system ([`System::setup`]): sets the safety block up
/// (ENABLE on every axis, outputs running at RUNNING with safe state SAFE,
/// CAUSE.WATCHDOG on IRQ), arms the watchdog, starts a slow move on every
/// axis, feeds it FEEDS times and then lets it bite; idles on 4 000 clocks.
pub fn run_into_bite<const N: usize>(sys: &mut System<N>) -> Bite {
    let all = (1u32 << N) - 1;
    sys.write("SAFETY", None, "ENABLE", all);
    sys.write("SAFETY", None, "GPO_SAFE", SAFE);
    sys.write("SAFETY", None, "GPO_OPEN_DRAIN", OPEN_DRAIN);
    sys.write("SAFETY", None, "GPO_VALUE", RUNNING);
    sys.write("SAFETY", None, "CAUSE_MASK", 2);
    let (segments, _) = creep(200);
    for axis in 0..N as u32 {
        for s in &segments {
            sys.push(axis, s);
        }
    }
    sys.write("SAFETY", None, "WDT_TIMEOUT", TIMEOUT);
    sys.write("PULSE", None, "RUN", all);
    for _ in 0..FEEDS {
        sys.idle(FEED_EVERY);
        sys.write("SAFETY", None, "WDT_RELOAD", WATCHDOG_KEY);
    }
    let last_feed = sys.clocks;
    while sys.drive_enable() != 0 {
        sys.idle(1);
        assert!(sys.clocks < last_feed + u64::from(TIMEOUT) + 100, "no bite");
    }
    let disabled_at = sys.clocks;
    // Steps already on the pins reach the shafts: 2 pin registers and the
    // drive's latency.
    sys.idle(2 + DRIVE_LATENCY as u64);
    let at_bite = sys.drives.iter().map(|d| d.position).collect();
    sys.idle(4_000);
    let later = sys.drives.iter().map(|d| d.position).collect();
    Bite {
        last_feed,
        disabled_at,
        at_bite,
        later,
    }
}

/// `motionhdl trace watchdog_bite`: two axes creep, firmware feeds the
/// watchdog four times and then stops; it bites, the drives and the
/// steps stop, the outputs take their safe state and IRQ falls.
pub fn trace(config: &Config) -> Trace {
    let mut sys = two_axes(config, |c| c);
    sys.record_scenario(config, "watchdog_bite");
    let bite = run_into_bite(&mut sys);
    assert_eq!(
        bite.later, bite.at_bite,
        "watchdog trace: no step after the bite"
    );
    assert!(!sys.irq(), "watchdog trace: IRQ low");
    sys.mark_edge("machine.drive_enable", 0, 0, "bite: drives off");
    sys.take_trace().expect("recording")
}
