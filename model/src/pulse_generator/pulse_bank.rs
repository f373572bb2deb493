//! The pulse generators behind the register bus, with their output stages.

use super::{MoveEngine, PulseGenerator, PulseInputs, Request, SegmentField, StepTiming};
use crate::counter::BusCycle;
use crate::pulse_mode_selector::RegisteredSelector;
use crate::regmap::{self, Block};

/// Quadrature A/B for a position: Gray phase position mod 4 = 00, 10, 11,
/// 01 (A leads B when the position rises).
pub fn quadrature(position: u32) -> (bool, bool) {
    let p = position & 3;
    (p == 1 || p == 2, p == 2 || p == 3)
}

/// What the safety block asks of the bank in one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stops {
    /// HALT: every axis stops.
    pub halt: bool,
    /// Per axis: no step in the positive direction; an axis heading that
    /// way stops.
    pub up: u32,
    /// Per axis: no step in the negative direction.
    pub down: u32,
    /// Per axis: the home event; HOME_POSITION captures POSITION.
    pub home: u32,
}

/// The bank of pulse generators behind the register bus
/// (`regmap::pulse_bank`), each feeding a registered pulse-mode selector.
/// Bus contract as the counter bank's: a write acts at the edge where `we`
/// is high; the edge where `re` is high takes the address, the next loads
/// `rdata`, which then holds.
#[derive(Clone, Debug)]
pub struct PulseBank {
    map: Block,
    width: u32,
    run: u32,
    ctrl: Vec<u32>,
    rate: Vec<u32>,
    step_timing: Vec<u32>,
    dir_timing: Vec<u32>,
    low_water: Vec<u32>,
    engines: Vec<MoveEngine>,
    snap: Vec<u32>,
    home_position: Vec<u32>,
    soft_min: Vec<u32>,
    soft_max: Vec<u32>,
    decel: Vec<u32>,
    /// The stops (up, down) at the edge before: a stop brakes only from
    /// the edge it arrives.
    stops_before: (u32, u32),
    /// Per axis: POSITION >= SOFT_MAX, POSITION <= SOFT_MIN, registered.
    above_max: u32,
    below_min: u32,
    generators: Vec<PulseGenerator>,
    selectors: Vec<RegisteredSelector>,
    quadrature: Vec<(bool, bool)>,
    out: Vec<(bool, bool)>,
    read_pending: bool,
    read_addr: u32,
    rdata: u32,
}

impl PulseBank {
    pub fn new(axes: u32, width: u32) -> Self {
        let n = axes as usize;
        Self {
            map: regmap::pulse_bank(axes, width),
            width,
            run: 0,
            ctrl: vec![0; n],
            rate: vec![0; n],
            step_timing: vec![0; n],
            dir_timing: vec![0; n],
            low_water: vec![0; n],
            engines: vec![MoveEngine::default(); n],
            snap: vec![0; n],
            stops_before: (0, 0),
            home_position: vec![0; n],
            soft_min: vec![0; n],
            soft_max: vec![0; n],
            decel: vec![0; n],
            above_max: 0,
            below_min: 0,
            generators: vec![PulseGenerator::new(); n],
            selectors: vec![RegisteredSelector::default(); n],
            quadrature: vec![(false, false); n],
            out: vec![(false, false); n],
            read_pending: false,
            read_addr: 0,
            rdata: 0,
        }
    }

    pub fn axes(&self) -> usize {
        self.generators.len()
    }

    pub fn generator(&self, i: usize) -> &PulseGenerator {
        &self.generators[i]
    }

    /// F1 and F2 of axis `i`: the registered selector's outputs, or with
    /// CTRL.QUADRATURE the quadrature A/B, through one more register.
    pub fn outputs(&self, i: usize) -> (bool, bool) {
        self.out[i]
    }

    pub fn rdata(&self) -> u32 {
        self.rdata
    }

    /// The move engine of axis `i`.
    pub fn engine(&self, i: usize) -> &MoveEngine {
        &self.engines[i]
    }

    fn moves(&self, i: usize) -> bool {
        self.ctrl[i] >> 2 & 1 == 1
    }

    fn inputs(&self, i: usize, halt: bool) -> PulseInputs {
        let braking = self.engines[i].braking();
        PulseInputs {
            enable: self.run >> i & 1 == 1 || braking,
            halt,
            rate: if self.moves(i) || braking {
                self.engines[i].rate()
            } else {
                self.rate[i] as i32
            },
            timing: StepTiming {
                step_len: self.step_timing[i] & 0xffff,
                step_space: self.step_timing[i] >> 16,
                dir_setup: self.dir_timing[i] & 0xffff,
                dir_hold: self.dir_timing[i] >> 16,
            },
        }
    }

    /// Whether `addr` is register `name` of axis `i`.
    fn is(&self, addr: u32, name: &str, i: usize) -> bool {
        addr & ((1 << self.map.address_bits) - 1) == self.map.array("AX").address(i as u32, name)
    }

    /// What a read of `addr` returns (0 where nothing is decoded).
    pub fn read_value(&self, addr: u32) -> u32 {
        let addr = addr & ((1 << self.map.address_bits) - 1);
        for (offset, r, index) in self.map.decoded() {
            if offset != addr {
                continue;
            }
            return match (r.name, index) {
                ("INFO", None) => r.reset,
                ("RUN", None) => self.run,
                (name, Some(i)) => {
                    let i = i as usize;
                    match name {
                        "CTRL" => self.ctrl[i],
                        "RATE" => self.rate[i],
                        "STEP_TIMING" => self.step_timing[i],
                        "DIR_TIMING" => self.dir_timing[i],
                        "FIFO_LOW_WATER" => self.low_water[i],
                        "DECEL" => self.decel[i],
                        "POSITION" => crate::counter::sign_extend(self.snap[i], self.width),
                        "SOFT_MIN" => crate::counter::sign_extend(self.soft_min[i], self.width),
                        "SOFT_MAX" => crate::counter::sign_extend(self.soft_max[i], self.width),
                        "HOME_POSITION" => {
                            crate::counter::sign_extend(self.home_position[i], self.width)
                        }
                        // Write-only: they write the FIFO's tail slot
                        // (reading them back would cost a 128-bit read-mux
                        // leg per axis).
                        "SEG_STEPS" | "SEG_RATE" | "SEG_ACCEL" | "SEG_JERK" | "SEG_PUSH" => 0,
                        "STATUS" => {
                            let t = self.generators[i].timer.state();
                            let e = &self.engines[i];
                            let busy = self.generators[i].busy();
                            (t.pending as u32 & 0xffff)
                                | u32::from(busy) << 16
                                | u32::from(e.active()) << 17
                                | u32::from(e.done()) << 18
                                | u32::from(e.overflow()) << 19
                                | (e.level() as u32) << 20
                                | u32::from(e.level() as u32 <= self.low_water[i]) << 27
                                | u32::from(e.braking()) << 28
                        }
                        _ => unreachable!("PULSE.AX.{name}"),
                    }
                }
                (name, None) => unreachable!("PULSE.{name}"),
            };
        }
        0
    }

    /// STATUS.DONE and not STATUS.BUSY: axis `i`'s move is out (the
    /// safety block's `done` input).
    pub fn move_done(&self, i: usize) -> bool {
        self.engines[i].done() && !self.generators[i].busy()
    }

    /// Per axis (POSITION >= SOFT_MAX, POSITION <= SOFT_MIN) as the
    /// flip-flops hold them: the safety block's soft-limit inputs.
    pub fn soft_levels(&self) -> (u32, u32) {
        (self.above_max, self.below_min)
    }

    /// The rate axis `i`'s NCO runs at in this clock: RATE, or with
    /// CTRL.MOVES or while braking the move engine's.
    pub fn nco_rate(&self, i: usize) -> i32 {
        self.inputs(i, false).rate
    }

    /// STATUS.FIFO_LOW of axis `i` (the safety block's `low` input).
    pub fn fifo_low(&self, i: usize) -> bool {
        self.engines[i].level() as u32 <= self.low_water[i]
    }

    /// One rising clock edge.
    pub fn clock(&mut self, reset: bool, bus: &BusCycle, snapshot: bool) {
        self.clock_stopping(reset, bus, snapshot, &Stops::default());
    }

    /// Axis `i` heads up (down): its NCO rate is positive (negative), or
    /// steps up (down) wait in its queue.
    fn heading(&self, i: usize) -> (bool, bool) {
        let rate = self.inputs(i, false).rate;
        let pending = self.generators[i].timer.state().pending;
        (rate > 0 || pending > 0, rate < 0 || pending < 0)
    }

    /// Whether axis `i` stops at once at this edge: HALT, or a stop in
    /// the direction it heads that does not brake.
    fn stopped(&self, i: usize, stops: &Stops) -> bool {
        let (up, down) = self.heading(i);
        let hit =
            stops.halt || (up && stops.up >> i & 1 == 1) || (down && stops.down >> i & 1 == 1);
        hit && !self.brakes(i, stops)
    }

    /// Whether axis `i` brakes at this edge: DECEL set, no HALT, and its
    /// NCO rate heads into a stop that has just arrived (or that its brake
    /// is running from).
    fn brakes(&self, i: usize, stops: &Stops) -> bool {
        let rate = self.nco_rate(i);
        // A stop counts from the edge it arrives, or while its brake runs.
        let live = |now: u32, before: u32| {
            now >> i & 1 == 1 && (before >> i & 1 == 0 || self.engines[i].braking())
        };
        let into = (rate > 0 && live(stops.up, self.stops_before.0))
            || (rate < 0 && live(stops.down, self.stops_before.1));
        !stops.halt && self.decel[i] != 0 && into
    }

    /// One edge with the safety block's stops. A stopped axis (HALT, or a
    /// stop in the direction it heads) has its RUN bit cleared (a write of
    /// it is ignored), its segment FIFO emptied and its queued steps
    /// dropped.
    pub fn clock_stopping(&mut self, reset: bool, bus: &BusCycle, snapshot: bool, stops: &Stops) {
        if reset {
            // The segment slots are block RAM: they keep their words.
            let mut engines = std::mem::take(&mut self.engines);
            engines.iter_mut().for_each(MoveEngine::reset);
            *self = Self {
                engines,
                ..Self::new(self.axes() as u32, self.width)
            };
            return;
        }
        if self.read_pending {
            self.rdata = self.read_value(self.read_addr);
        }
        self.read_pending = bus.re;
        if bus.re {
            self.read_addr = bus.addr;
        }
        let stopped = (0..self.axes())
            .filter(|&i| self.stopped(i, stops))
            .fold(0u32, |mask, i| mask | 1 << i);
        let braking = (0..self.axes())
            .filter(|&i| self.brakes(i, stops))
            .fold(0u32, |mask, i| mask | 1 << i);
        for i in 0..self.axes() {
            let halt = stopped >> i & 1 == 1;
            let inputs = self.inputs(i, halt);
            self.out[i] = if self.ctrl[i] >> 1 & 1 == 1 {
                self.quadrature[i]
            } else {
                self.selectors[i].outputs()
            };
            self.quadrature[i] = quadrature(self.generators[i].position);
            let (s1, s2) = self.generators[i].outputs();
            self.selectors[i].clock(false, self.ctrl[i] & 1 == 1, s2, s1);
            let position = crate::counter::wrap(self.generators[i].position, self.width);
            if snapshot {
                self.snap[i] = position;
            }
            if stops.home >> i & 1 == 1 {
                self.home_position[i] = position;
            }
            // Signed WIDTH-bit compares, registered.
            let signed = |v: u32| crate::counter::sign_extend(v, self.width) as i32;
            let bit = 1 << i;
            self.above_max &= !bit;
            self.below_min &= !bit;
            if signed(position) >= signed(self.soft_max[i]) {
                self.above_max |= bit;
            }
            if signed(position) <= signed(self.soft_min[i]) {
                self.below_min |= bit;
            }
            let (request, blocked) = self.generators[i].request(&inputs);
            let push = bus.we && self.is(bus.addr, "SEG_PUSH", i);
            let writes: Vec<(SegmentField, u32)> = [
                ("SEG_STEPS", SegmentField::Steps),
                ("SEG_RATE", SegmentField::Rate),
                ("SEG_ACCEL", SegmentField::Accel),
                ("SEG_JERK", SegmentField::Jerk),
            ]
            .into_iter()
            .filter(|(name, _)| bus.we && self.is(bus.addr, name, i))
            .map(|(_, f)| (f, bus.wdata))
            .collect();
            let moves = self.moves(i);
            let was_braking = self.engines[i].braking();
            self.engines[i].clock_bus(
                moves && self.run >> i & 1 == 1,
                moves && request != Request::None,
                (moves || was_braking) && inputs.enable && !halt && !blocked,
                &writes,
                push,
            );
            if halt {
                self.engines[i].flush();
            } else if braking >> i & 1 == 1 {
                self.engines[i].brake(was_braking, inputs.rate, self.decel[i]);
            }
            self.generators[i].clock(&inputs, false);
        }
        if bus.we {
            let addr = bus.addr & ((1 << self.map.address_bits) - 1);
            let hit = self.map.decoded().into_iter().find(|(o, _, _)| *o == addr);
            if let Some((_, r, index)) = hit {
                let v = bus.wdata & r.writable_mask();
                match (r.name, index) {
                    ("RUN", None) => self.run = v,
                    ("CTRL", Some(i)) => {
                        self.ctrl[i as usize] = v;
                        self.engines[i as usize].clear_overflow();
                    }
                    ("RATE", Some(i)) => self.rate[i as usize] = v,
                    ("STEP_TIMING", Some(i)) => self.step_timing[i as usize] = v,
                    ("DIR_TIMING", Some(i)) => self.dir_timing[i as usize] = v,
                    ("FIFO_LOW_WATER", Some(i)) => self.low_water[i as usize] = v,
                    ("SOFT_MIN", Some(i)) => {
                        self.soft_min[i as usize] = crate::counter::wrap(v, self.width)
                    }
                    ("SOFT_MAX", Some(i)) => {
                        self.soft_max[i as usize] = crate::counter::wrap(v, self.width)
                    }
                    ("DECEL", Some(i)) => self.decel[i as usize] = v,
                    _ => {}
                }
            }
        }
        self.run &= !(stopped | braking);
        self.stops_before = (stops.up, stops.down);
    }
}

#[cfg(test)]
mod tests;
