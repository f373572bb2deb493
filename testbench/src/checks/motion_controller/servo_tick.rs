//! The servo tick's contract on the servo card's top (docs/servo_dac.md,
//! "In the top"), watched on the rust-hdl top while it runs beside the
//! model: the tick comes exactly TICK_PERIOD clocks after the last tick,
//! or TICK_PERIOD clocks after the clock that follows a write of
//! TICK_PERIOD (the write's edge restarts the count), and at no other
//! clock; at the tick's
//! edge every counter channel's snapshot takes the count as it stood in
//! that clock; a tick that finds the DAC interface free starts the
//! transfer at its own edge, so LOADDACS rises exactly `update_latency`
//! edges later (`serial_update_latency` with SERIAL.MODE = 1).

use crate::checks::motion_controller::top_model::ModelledTop;
use crate::checks::servo_dac::update_latency_of;
use crate::state_map;
use motionhdl_model::motion_controller::MotionControllerModel;
use std::collections::VecDeque;

/// One clock as the watch sees it, before its edge.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TickSample {
    pub reset: bool,
    /// The SERVO block's tick.
    pub tick: bool,
    /// A write of TICK_PERIOD in this clock, its value.
    pub period_write: Option<u32>,
    /// Every counter channel's count now.
    pub counts: Vec<u32>,
    /// The LOADDACS pin now.
    pub ldac_n: bool,
    /// With the DAC interface free (no transfer running or waiting): the
    /// update latency of its TIMING now.
    pub free_latency: Option<u32>,
}

impl TickSample {
    /// The sample of the rust-hdl servo top `uut` and the model beside it
    /// (both before the edge), with `reset` and the LOADDACS pin.
    pub fn of<const N: usize, T: ModelledTop<N>>(
        uut: &T,
        model: &MotionControllerModel,
        reset: bool,
        ldac_n: bool,
    ) -> Self {
        let mcu = uut.mcu();
        let servo = model.servo().expect("the servo card's model");
        let map = servo.map();
        let read = |name: &str| servo.read_value(map.register(name).offset);
        let status = map.register("STATUS");
        let busy = status.field("BUSY").mask() | status.field("PENDING").mask();
        let latency = update_latency_of(map, read("TIMING"), read("SERIAL"));
        let period_offset = map.register("TICK_PERIOD").offset;
        let wrote_period =
            mcu.servo_we.val() && mcu.servo_addr.val().index() as u32 == period_offset;
        Self {
            reset,
            tick: mcu.servo_tick.val(),
            period_write: wrote_period.then(|| mcu.servo_wdata.val().index() as u32),
            counts: counts(uut, |s| s.count),
            ldac_n,
            free_latency: (read("STATUS") & busy == 0).then_some(latency),
        }
    }
}

/// Every counter channel's `field` of the HDL's state.
pub fn counts<const N: usize, T: ModelledTop<N>>(
    uut: &T,
    field: fn(&motionhdl_model::counter::ChannelState) -> u32,
) -> Vec<u32> {
    (0..N)
        .map(|i| field(&state_map::channel(uut.mcu().counters().channel(i).probe())))
        .collect()
}

/// What the watch saw, and every clock where the contract broke.
#[derive(Clone, Debug, Default)]
pub struct TickWatch {
    period: u32,
    last_event: Option<u64>,
    counts_at_tick: Option<Vec<u32>>,
    /// Samples at which LOADDACS must be seen rising (low in the one
    /// before).
    due: VecDeque<u64>,
    /// Ticks seen, and those at the clock the period gave.
    pub ticks: u64,
    pub on_time: u64,
    /// Snapshots checked (channels x ticks).
    pub snapshots: u64,
    /// LOADDACS rises checked (ticks that found the interface free).
    pub loads: u64,
    pub violations: Vec<String>,
}

impl TickWatch {
    /// Sample `k`, before its edge.
    pub fn before_edge(&mut self, k: u64, s: &TickSample) {
        if self.due.front() == Some(&k) {
            self.due.pop_front();
            self.loads += 1;
            if !s.ldac_n {
                self.violations.push(format!(
                    "clock {k}: LOADDACS not high where it must have risen"
                ));
            }
        }
        if self.due.front() == Some(&(k + 1)) && s.ldac_n {
            self.violations.push(format!(
                "clock {k}: LOADDACS high the clock before its rise"
            ));
        }
        if s.reset {
            self.counts_at_tick = None;
            self.period = 0;
            self.last_event = None;
            self.due.clear();
            return;
        }
        let expected = self.period > 0
            && self
                .last_event
                .is_some_and(|j| j + u64::from(self.period) == k);
        if s.tick != expected {
            self.violations.push(format!(
                "clock {k}: tick {}, expected {expected} (period {}, counting from {:?})",
                s.tick, self.period, self.last_event
            ));
        }
        if s.tick {
            self.ticks += 1;
            self.on_time += u64::from(expected);
            self.last_event = Some(k);
            self.counts_at_tick = Some(s.counts.clone());
            if let Some(latency) = s.free_latency {
                self.due.push_back(k + u64::from(latency) + 1);
            }
        }
        if let Some(period) = s.period_write {
            // The count restarts at this clock's edge: clock k + 1 is the
            // period's first.
            self.period = period;
            self.last_event = Some(k + 1);
        }
    }

    /// After the edge of sample `k`: `snapshots`, every channel's snapshot
    /// count now. A tick's snapshot holds the counts of its clock.
    pub fn after_edge(&mut self, k: u64, snapshots: &[u32]) {
        let Some(counts) = self.counts_at_tick.take() else {
            return;
        };
        for (i, (&got, want)) in snapshots.iter().zip(counts).enumerate() {
            self.snapshots += 1;
            if got != want {
                self.violations.push(format!(
                    "clock {k}: channel {i} snapshot {got:#x}, count at the tick {want:#x}"
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TICKS: [u64; 6] = [10, 14, 18, 22, 26, 30];

    /// A stream that keeps the contract: reset, TICK_PERIOD = 4 written in
    /// clock 5, ticks from clock 10 on; a latency of 3 (LOADDACS low in the
    /// clock 3 after the tick, high after); `counts` = [k].
    fn stream() -> Vec<(TickSample, u32)> {
        (0..32u64)
            .map(|k| {
                let tick = TICKS.contains(&k);
                let sample = TickSample {
                    reset: k < 3,
                    tick,
                    period_write: (k == 5).then_some(4),
                    counts: vec![k as u32],
                    ldac_n: !TICKS.contains(&(k.wrapping_sub(3))),
                    free_latency: tick.then_some(3),
                };
                // The snapshot after the edge: the count of the last tick.
                let snap = TICKS
                    .iter()
                    .rev()
                    .find(|&&t| t <= k)
                    .map_or(0, |&t| t as u32);
                (sample, snap)
            })
            .collect()
    }

    fn watch(stream: &[(TickSample, u32)]) -> TickWatch {
        let mut w = TickWatch::default();
        for (k, (s, snap)) in stream.iter().enumerate() {
            w.before_edge(k as u64, s);
            w.after_edge(k as u64, &[*snap]);
        }
        w
    }

    #[test]
    fn a_stream_that_keeps_the_contract_passes() {
        let w = watch(&stream());
        assert!(w.violations.is_empty(), "{:?}", w.violations);
        assert_eq!((w.ticks, w.on_time, w.snapshots), (6, 6, 6));
        // LOADDACS of the ticks up to 26 (the last one, 30, is due later).
        assert_eq!(w.loads, 5);
    }

    #[test]
    fn each_breakage_is_caught() {
        // A tick one clock late.
        let mut s = stream();
        s[14].0.tick = false;
        s[15].0.tick = true;
        assert!(watch(&s).violations.len() >= 2);
        // A snapshot that missed the tick's count.
        let mut s = stream();
        s[18].1 = 17;
        assert_eq!(watch(&s).violations.len(), 1);
        // LOADDACS one clock late.
        let mut s = stream();
        s[21].0.ldac_n = true;
        s[22].0.ldac_n = false;
        assert!(!watch(&s).violations.is_empty());
        // The first tick counted from the write's clock, not the next.
        let mut s = stream();
        s[10].0.tick = false;
        s[9].0.tick = true;
        assert!(!watch(&s).violations.is_empty());
    }
}
