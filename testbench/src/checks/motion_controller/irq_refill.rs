//! A long move streamed on interrupts alone (docs/safety_io.md, "Causes
//! and the IRQ pin"; docs/pulse_generator.md, the segment FIFO's
//! low-water mark): the firmware fills the FIFOs, starts the axes and then
//! only waits for the IRQ pin; at each interrupt it reads LOW_CAUSE and
//! DONE_CAUSE, refills the axes whose FIFO fell to the mark, and clears
//! what it handled. It never reads STATUS.

use super::limit_stop::creep;
use super::system::{two_axes, System};
use crate::trace::Trace;
use motionhdl_model::pulse_generator::{Segment, SEGMENT_FIFO_DEPTH};
use motionhdl_model::Config;

/// How a streamed move went.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Refill {
    /// Interrupts the firmware took.
    pub interrupts: u32,
    /// Register reads in the interrupt loop (two per interrupt: no
    /// polling).
    pub reads: u32,
    /// Per axis: refills (LOW_CAUSE bits handled with segments left).
    pub refills: Vec<u32>,
    /// Clocks from RUN to the last DONE.
    pub clocks: u64,
}

/// `segments` segments of `steps` steps at one step per `period` clocks,
/// forward.
pub fn steady(segments: usize, steps: u32, period: i64) -> Vec<Segment> {
    let (one, _) = creep(i64::from(steps));
    let rate = ((1i64 << 32) / period) as i32;
    vec![Segment { rate, ..one[0] }; segments]
}

/// Streams `per_axis` (one list per axis, every axis moving) with the
/// FIFO_LOW_WATER mark at `low_water`: fills every FIFO, starts the axes in
/// one RUN write, then serves interrupts until every axis's DONE_CAUSE has
/// risen with no segment left. `Err` if an axis ran dry (DONE before its
/// last segment) or the move takes longer than `timeout` clocks.
pub fn stream_on_irq<const N: usize>(
    sys: &mut System<N>,
    per_axis: &[Vec<Segment>],
    low_water: u32,
    timeout: u64,
) -> Result<Refill, String> {
    assert_eq!(per_axis.len(), N);
    assert!((1..SEGMENT_FIFO_DEPTH as u32).contains(&low_water));
    let all = (1u32 << N) - 1;
    let mut next = vec![0usize; N];
    for i in 0..N {
        sys.write("PULSE", Some(i as u32), "FIFO_LOW_WATER", low_water);
        push_up_to(sys, i, &per_axis[i], &mut next[i], SEGMENT_FIFO_DEPTH);
    }
    // The fill raised FIFO_LOW's level above the mark; what the empty
    // FIFOs set before is old news.
    sys.write("SAFETY", None, "LOW_CAUSE", all);
    sys.write("SAFETY", None, "DONE_CAUSE", all);
    sys.write("SAFETY", None, "LOW_MASK", all);
    sys.write("SAFETY", None, "DONE_MASK", all);
    sys.write("PULSE", None, "RUN", all);
    let start = sys.clocks;
    let mut out = Refill {
        refills: vec![0; N],
        ..Refill::default()
    };
    let mut finished = 0u32;
    while finished != all {
        // The MCU sleeps until the IRQ pin (active low) falls.
        while sys.irq() {
            sys.idle(1);
            if sys.clocks - start > timeout {
                return Err(format!("no interrupt within {timeout} clocks"));
            }
        }
        out.interrupts += 1;
        let low = sys.read("SAFETY", None, "LOW_CAUSE");
        let done = sys.read("SAFETY", None, "DONE_CAUSE");
        out.reads += 2;
        for i in (0..N).filter(|i| low >> i & 1 == 1) {
            // At most the mark was left when the cause rose: room for the
            // rest of the FIFO.
            let room = SEGMENT_FIFO_DEPTH - low_water as usize;
            if push_up_to(sys, i, &per_axis[i], &mut next[i], room) > 0 {
                out.refills[i] += 1;
            }
        }
        if low != 0 {
            sys.write("SAFETY", None, "LOW_CAUSE", low);
        }
        for i in (0..N).filter(|i| done >> i & 1 == 1) {
            if next[i] < per_axis[i].len() {
                return Err(format!(
                    "axis {i} ran dry: DONE with {} of {} segments pushed",
                    next[i],
                    per_axis[i].len()
                ));
            }
            finished |= 1 << i;
        }
        if done != 0 {
            sys.write("SAFETY", None, "DONE_CAUSE", done);
        }
    }
    out.clocks = sys.clocks - start;
    Ok(out)
}

/// Pushes up to `room` of `segs` from `*next` on to `axis`; how many.
fn push_up_to<const N: usize>(
    sys: &mut System<N>,
    axis: usize,
    segs: &[Segment],
    next: &mut usize,
    room: usize,
) -> usize {
    let end = segs.len().min(*next + room);
    for s in &segs[*next..end] {
        sys.push(axis as u32, s);
    }
    let pushed = end - *next;
    *next = end;
    pushed
}

/// Segments, their steps and the low-water mark of the trace: 8-step
/// segments at one step per 40 clocks (320 clocks each); a refill of two
/// axes' 32 segments takes about 6 400 clocks of bus writes, the 32 left
/// last 10 240.
pub const TRACE_SEGMENTS: usize = 96;
pub const TRACE_STEPS: u32 = 8;
pub const TRACE_LOW_WATER: u32 = 32;

/// `motionhdl trace irq_refill`: two axes stream 96 segments each on the
/// FIFO-low interrupt, the firmware never reading STATUS.
pub fn trace(config: &Config) -> Trace {
    let mut sys = two_axes(config, |c| c);
    sys.record_scenario(config, "irq_refill");
    let segs = steady(TRACE_SEGMENTS, TRACE_STEPS, 40);
    let r = stream_on_irq(&mut sys, &[segs.clone(), segs], TRACE_LOW_WATER, 1 << 20)
        .expect("irq_refill trace: the move streams");
    assert_eq!(r.reads, 2 * r.interrupts, "irq_refill trace: no polling");
    sys.mark_edge("mcu.irq", 0, 0, "first FIFO-low IRQ");
    sys.idle(200);
    let target = (TRACE_SEGMENTS as u32 * TRACE_STEPS) as i32;
    assert_eq!(
        sys.drives[0].position, target,
        "irq_refill trace: on target"
    );
    sys.take_trace().expect("recording")
}
