//! Step/pulse generator of one axis (docs/pulse_generator.md): an NCO that
//! commands steps, a signed queue of commanded-but-not-yet-emitted steps, and
//! the output timing state machine that emits them as S1 (step) and S2
//! (direction) with minimum step length, step space, direction set-up and
//! direction hold. A step that would violate a timing waits in the queue; no
//! step is ever dropped.

use crate::counter::BusCycle;
use crate::pulse_mode_selector::RegisteredSelector;
use crate::regmap::{self, Block};
pub use motionhdl_spec::pulse::{Segment, PENDING_BITS, SEGMENT_FIFO_DEPTH, TIMER_BITS};

/// Minimum times, in clocks (0 counts as 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct StepTiming {
    /// S1 high for at least this many clocks.
    pub step_len: u32,
    /// S1 low for at least this many clocks between steps.
    pub step_space: u32,
    /// S2 stable for at least this many clocks before S1 rises.
    pub dir_setup: u32,
    /// S1 low for at least this many clocks before S2 changes.
    pub dir_hold: u32,
}

/// One clock's request from the NCO (or a test) to the step timer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Request {
    #[default]
    None,
    /// One step in the positive direction.
    Up,
    /// One step in the negative direction.
    Down,
}

/// The step timer's registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct StepTimerState {
    /// Commanded minus emitted steps.
    pub pending: i32,
    /// S1.
    pub step: bool,
    /// S2: 1 = negative direction (the counter bank's PULSE_DIR convention).
    pub dir: bool,
    /// Clocks S1 has held its level, counting the clock after the edge that
    /// set it as 1; saturates at the timer's maximum.
    pub t_step: u32,
    /// Clocks S2 has held its level, the same way.
    pub t_dir: u32,
}

/// The output timing state machine with a `pending_bits`-bit queue and
/// `timer_bits`-bit timers (16 and 16 in the gateware; narrower for
/// exhaustive checks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepTimer {
    pending_bits: u32,
    timer_bits: u32,
    state: StepTimerState,
}

impl StepTimer {
    pub fn new(pending_bits: u32, timer_bits: u32) -> Self {
        assert!(
            (2..=16).contains(&pending_bits),
            "pending_bits = {pending_bits} out of range 2..=16"
        );
        assert!(
            (1..=16).contains(&timer_bits),
            "timer_bits = {timer_bits} out of range 1..=16"
        );
        let mut t = Self {
            pending_bits,
            timer_bits,
            state: StepTimerState {
                pending: 0,
                step: false,
                dir: false,
                t_step: 0,
                t_dir: 0,
            },
        };
        t.reset();
        t
    }

    /// Largest queue magnitude: the NCO holds rather than go past it.
    pub fn pending_max(&self) -> i32 {
        (1 << (self.pending_bits - 1)) - 1
    }

    pub fn timer_max(&self) -> u32 {
        (1 << self.timer_bits) - 1
    }

    pub fn state(&self) -> StepTimerState {
        self.state
    }

    pub fn set_state(&mut self, s: StepTimerState) {
        self.state = s;
    }

    pub fn reset(&mut self) {
        self.state = StepTimerState {
            pending: 0,
            step: false,
            dir: false,
            t_step: self.timer_max(),
            t_dir: self.timer_max(),
        };
    }

    /// Whether the queue can take `request` this clock (else the NCO holds).
    pub fn accepts(&self, request: Request) -> bool {
        match request {
            Request::None => true,
            Request::Up => self.state.pending < self.pending_max(),
            Request::Down => self.state.pending > -self.pending_max(),
        }
    }

    /// The step emitted at this edge, if any: +1 or -1.
    pub fn emits(&self, timing: &StepTiming) -> i32 {
        let s = &self.state;
        let want_negative = s.pending < 0;
        if !s.step
            && s.pending != 0
            && s.dir == want_negative
            && s.t_step >= timing.step_space
            && s.t_dir >= timing.dir_setup
        {
            if s.dir {
                -1
            } else {
                1
            }
        } else {
            0
        }
    }

    /// One rising clock edge. `request` must be one [`StepTimer::accepts`].
    pub fn clock(&mut self, request: Request, timing: &StepTiming) {
        assert!(
            self.accepts(request),
            "request {request:?} with pending {}",
            self.state.pending
        );
        let max = self.timer_max();
        let inc = |t: u32| if t < max { t + 1 } else { t };
        let s = self.state;
        let emit = self.emits(timing);
        let mut n = s;
        n.t_step = inc(s.t_step);
        n.t_dir = inc(s.t_dir);
        if s.step {
            if s.t_step >= timing.step_len {
                n.step = false;
                n.t_step = 1;
            }
        } else if emit != 0 {
            n.step = true;
            n.t_step = 1;
        } else if s.pending != 0 && s.dir != (s.pending < 0) && s.t_step >= timing.dir_hold {
            n.dir = !s.dir;
            n.t_dir = 1;
        }
        let commanded = match request {
            Request::None => 0,
            Request::Up => 1,
            Request::Down => -1,
        };
        n.pending = s.pending + commanded - emit;
        self.state = n;
    }
}

/// The whole axis: NCO, step timer and position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PulseGenerator {
    /// NCO phase accumulator.
    pub phase: u32,
    /// Emitted steps, signed, modulo 2^32.
    pub position: u32,
    pub timer: StepTimer,
}

/// One clock's inputs of the axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PulseInputs {
    /// The NCO runs; without it, queued steps still go out.
    pub enable: bool,
    /// Signed rate: steps per clock = rate / 2^32 (|rate| <= 2^31: f/2).
    pub rate: i32,
    pub timing: StepTiming,
}

impl Default for PulseGenerator {
    fn default() -> Self {
        Self::new()
    }
}

impl PulseGenerator {
    pub fn new() -> Self {
        Self {
            phase: 0,
            position: 0,
            timer: StepTimer::new(PENDING_BITS, TIMER_BITS),
        }
    }

    /// S1 and S2.
    pub fn outputs(&self) -> (bool, bool) {
        (self.timer.state.step, self.timer.state.dir)
    }

    /// The NCO's request at this edge, and whether the queue holds it back
    /// (then the phase does not advance either).
    pub fn request(&self, inp: &PulseInputs) -> (Request, bool) {
        if !inp.enable {
            return (Request::None, false);
        }
        let sum = u64::from(self.phase) + u64::from(inp.rate.unsigned_abs());
        let request = match (sum >> 32 != 0, inp.rate < 0) {
            (false, _) => Request::None,
            (true, false) => Request::Up,
            (true, true) => Request::Down,
        };
        let blocked = !self.timer.accepts(if inp.rate < 0 {
            Request::Down
        } else {
            Request::Up
        });
        (if blocked { Request::None } else { request }, blocked)
    }

    /// One rising clock edge.
    pub fn clock(&mut self, inp: &PulseInputs, reset: bool) {
        if reset {
            *self = Self::new();
            return;
        }
        let (request, blocked) = self.request(inp);
        let emit = self.timer.emits(&inp.timing);
        if inp.enable && !blocked {
            self.phase = self.phase.wrapping_add(inp.rate.unsigned_abs());
        }
        self.position = self.position.wrapping_add(emit as u32);
        self.timer.clock(request, &inp.timing);
    }
}

/// A field of the segment being written (the SEG_* registers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentField {
    Steps,
    Rate,
    Accel,
}

/// Position moves: a FIFO of segments the MCU streams (e.g. to follow an
/// S-curve) and the segment being run. The SEG_* writes go straight into
/// the FIFO's free tail slot (no staging registers: 96 flip-flops less per
/// axis); while the FIFO is full they are dropped, and a PUSH then
/// overflows. A slot keeps what was last written into it, so fields not
/// written since the slot last held a segment carry that old value.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MoveEngine {
    slots: [Segment; SEGMENT_FIFO_DEPTH],
    head: usize,
    count: usize,
    active: bool,
    rate: i32,
    accel: i32,
    remaining: u32,
    done: bool,
    overflow: bool,
}

impl MoveEngine {
    /// The NCO rate: the running segment's, or 0.
    pub fn rate(&self) -> i32 {
        if self.active {
            self.rate
        } else {
            0
        }
    }
    pub fn active(&self) -> bool {
        self.active
    }
    /// Sticky: every pushed segment has commanded all its steps (cleared
    /// by the next push).
    pub fn done(&self) -> bool {
        self.done
    }
    /// Sticky: a push found the FIFO full and was dropped (cleared by a
    /// CTRL write).
    pub fn overflow(&self) -> bool {
        self.overflow
    }
    pub fn level(&self) -> usize {
        self.count
    }
    /// (active, rate, remaining, done, overflow, level): the registers the
    /// gateware compares.
    pub fn probe(&self) -> (bool, u32, u32, bool, bool, u32) {
        (
            self.active,
            self.rate as u32,
            self.remaining,
            self.done,
            self.overflow,
            self.count as u32,
        )
    }
    pub fn clear_overflow(&mut self) {
        self.overflow = false;
    }

    /// One edge with a whole segment pushed at once (its three fields
    /// written into the tail slot and pushed in the same edge).
    pub fn clock(&mut self, run: bool, commanded: bool, advancing: bool, push: Option<Segment>) {
        let writes = push.map(|s| {
            [
                (SegmentField::Steps, s.steps),
                (SegmentField::Rate, s.rate as u32),
                (SegmentField::Accel, s.accel as u32),
            ]
        });
        self.clock_bus(
            run,
            commanded,
            advancing,
            writes.as_ref().map_or(&[][..], |w| &w[..]),
            push.is_some(),
        );
    }

    /// One edge. `run`: the axis's RUN bit; `commanded`: the NCO commanded
    /// a step this clock; `advancing`: the NCO's phase advanced; `writes`:
    /// SEG_* fields written this clock; `push`: SEG_PUSH written.
    pub fn clock_bus(
        &mut self,
        run: bool,
        commanded: bool,
        advancing: bool,
        writes: &[(SegmentField, u32)],
        push: bool,
    ) {
        let mut ended = false;
        // The tail slot, from the state before this edge (a pop moves head
        // and count together, so it names the same slot after it).
        let tail = (self.head + self.count) % SEGMENT_FIFO_DEPTH;
        if self.active {
            if commanded {
                self.remaining -= 1;
                if self.remaining == 0 {
                    self.active = false;
                    ended = true;
                }
            }
            if advancing {
                self.rate = self.rate.wrapping_add(self.accel);
            }
        } else if run && self.count > 0 {
            let seg = self.slots[self.head];
            self.head = (self.head + 1) % SEGMENT_FIFO_DEPTH;
            self.count -= 1;
            self.active = seg.steps != 0;
            ended = seg.steps == 0;
            self.rate = seg.rate;
            self.accel = seg.accel;
            self.remaining = seg.steps;
        }
        if ended && self.count == 0 {
            self.done = true;
        }
        if self.count < SEGMENT_FIFO_DEPTH {
            let slot = &mut self.slots[tail];
            for &(field, v) in writes {
                match field {
                    SegmentField::Steps => slot.steps = v,
                    SegmentField::Rate => slot.rate = v as i32,
                    SegmentField::Accel => slot.accel = v as i32,
                }
            }
        }
        if push {
            if self.count < SEGMENT_FIFO_DEPTH {
                self.count += 1;
                self.done = false;
            } else {
                self.overflow = true;
            }
        }
    }
}

/// Quadrature A/B for a position: Gray phase position mod 4 = 00, 10, 11,
/// 01 (A leads B when the position rises).
pub fn quadrature(position: u32) -> (bool, bool) {
    let p = position & 3;
    (p == 1 || p == 2, p == 2 || p == 3)
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
    engines: Vec<MoveEngine>,
    snap: Vec<u32>,
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
            engines: vec![MoveEngine::default(); n],
            snap: vec![0; n],
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

    fn inputs(&self, i: usize) -> PulseInputs {
        PulseInputs {
            enable: self.run >> i & 1 == 1,
            rate: if self.moves(i) {
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
                        "POSITION" => crate::counter::sign_extend(self.snap[i], self.width),
                        // Write-only: they write the FIFO's tail slot
                        // (reading them back would cost a 96-bit read-mux
                        // leg per axis).
                        "SEG_STEPS" | "SEG_RATE" | "SEG_ACCEL" | "SEG_PUSH" => 0,
                        "STATUS" => {
                            let t = self.generators[i].timer.state();
                            let e = &self.engines[i];
                            let busy = t.pending != 0 || t.step;
                            (t.pending as u32 & 0xffff)
                                | u32::from(busy) << 16
                                | u32::from(e.active()) << 17
                                | u32::from(e.done()) << 18
                                | u32::from(e.overflow()) << 19
                                | (e.level() as u32) << 20
                        }
                        _ => unreachable!("PULSE.AX.{name}"),
                    }
                }
                (name, None) => unreachable!("PULSE.{name}"),
            };
        }
        0
    }

    /// One rising clock edge.
    pub fn clock(&mut self, reset: bool, bus: &BusCycle, snapshot: bool) {
        if reset {
            *self = Self::new(self.axes() as u32, self.width);
            return;
        }
        if self.read_pending {
            self.rdata = self.read_value(self.read_addr);
        }
        self.read_pending = bus.re;
        if bus.re {
            self.read_addr = bus.addr;
        }
        for i in 0..self.axes() {
            let inputs = self.inputs(i);
            self.out[i] = if self.ctrl[i] >> 1 & 1 == 1 {
                self.quadrature[i]
            } else {
                self.selectors[i].outputs()
            };
            self.quadrature[i] = quadrature(self.generators[i].position);
            let (s1, s2) = self.generators[i].outputs();
            self.selectors[i].clock(false, self.ctrl[i] & 1 == 1, s2, s1);
            if snapshot {
                self.snap[i] = crate::counter::wrap(self.generators[i].position, self.width);
            }
            let (request, blocked) = self.generators[i].request(&inputs);
            let push = bus.we && self.is(bus.addr, "SEG_PUSH", i);
            let writes: Vec<(SegmentField, u32)> = [
                ("SEG_STEPS", SegmentField::Steps),
                ("SEG_RATE", SegmentField::Rate),
                ("SEG_ACCEL", SegmentField::Accel),
            ]
            .into_iter()
            .filter(|(name, _)| bus.we && self.is(bus.addr, name, i))
            .map(|(_, f)| (f, bus.wdata))
            .collect();
            let moves = self.moves(i);
            self.engines[i].clock_bus(
                moves && inputs.enable,
                moves && request != Request::None,
                moves && inputs.enable && !blocked,
                &writes,
                push,
            );
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
                    _ => {}
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timing(l: u32, s: u32, su: u32, h: u32) -> StepTiming {
        StepTiming {
            step_len: l,
            step_space: s,
            dir_setup: su,
            dir_hold: h,
        }
    }

    #[test]
    fn half_clock_rate_gives_a_step_every_other_clock() {
        let mut g = PulseGenerator::new();
        let inp = PulseInputs {
            enable: true,
            rate: i32::MIN,
            timing: timing(1, 1, 1, 1),
        };
        assert_eq!(inp.rate, i32::MIN);
        let mut rises = 0;
        let mut last = false;
        for _ in 0..1000 {
            g.clock(&inp, false);
            let (s, _) = g.outputs();
            rises += u32::from(s && !last);
            last = s;
        }
        // Negative full rate: 500 commanded, the first one after a
        // direction set-up of one clock.
        assert!((498..=500).contains(&rises), "{rises}");
        assert_eq!(g.position as i32, -(rises as i32));
    }

    #[test]
    fn pulses_honour_the_timing() {
        let t = timing(3, 2, 4, 5);
        let mut g = PulseGenerator::new();
        let mut hist = Vec::new();
        for k in 0..4000 {
            let rate = if (k / 1000) % 2 == 0 {
                1 << 29
            } else {
                -(1 << 29)
            };
            g.clock(
                &PulseInputs {
                    enable: k < 3500,
                    rate,
                    timing: t,
                },
                false,
            );
            hist.push(g.outputs());
        }
        // Runs of S1 high >= 3, low >= 2; S2 changes only with S1 low for
        // >= 5 clocks before and >= 4 clocks before the next rise.
        let mut k = 0;
        while k < hist.len() {
            let (s, _) = hist[k];
            let mut j = k;
            while j < hist.len() && hist[j].0 == s {
                j += 1;
            }
            if k > 0 && j < hist.len() {
                assert!(
                    j - k >= if s { 3 } else { 2 },
                    "run of {s} at {k}: {}",
                    j - k
                );
            }
            k = j;
        }
        for k in 1..hist.len() {
            if hist[k].1 != hist[k - 1].1 {
                assert!(!hist[k].0 && (k.saturating_sub(5)..k).all(|j| !hist[j].0));
                let next_rise = (k..hist.len()).find(|&j| hist[j].0);
                if let Some(r) = next_rise {
                    assert!(r - k >= 4);
                }
            }
        }
        assert_eq!(g.timer.state().pending, 0);
        assert!(!g.outputs().0);
    }

    /// SEG_* writes fill the tail slot; while the FIFO is full they are
    /// dropped, and a field not written keeps the slot's old contents.
    #[test]
    fn segment_writes_go_to_the_tail_slot_and_are_dropped_when_full() {
        use SegmentField::*;
        let mut e = MoveEngine::default();
        let write = |e: &mut MoveEngine, f: SegmentField, v: u32| {
            e.clock_bus(false, false, false, &[(f, v)], false)
        };
        let push = |e: &mut MoveEngine| e.clock_bus(false, false, false, &[], true);
        for (k, steps) in [(0u32, 5u32), (1, 7)] {
            write(&mut e, Steps, steps);
            write(&mut e, Rate, 100 + k);
            write(&mut e, Accel, 0);
            push(&mut e);
        }
        assert_eq!(e.level(), SEGMENT_FIFO_DEPTH);
        // Full: this write is dropped and the push overflows.
        write(&mut e, Steps, 99);
        push(&mut e);
        assert!(e.overflow());
        assert_eq!(e.level(), SEGMENT_FIFO_DEPTH);
        // Run the first segment in: a slot frees, and only RATE is
        // written into it, so its steps are the old slot's (5).
        e.clock_bus(true, false, false, &[], false);
        assert!(e.active() && e.rate() == 100, "{e:?}");
        write(&mut e, Rate, 300);
        push(&mut e);
        for want in [(7, 101), (5, 300)] {
            // Finish the running segment, then load the next.
            while e.active() {
                e.clock_bus(true, true, false, &[], false);
            }
            e.clock_bus(true, false, false, &[], false);
            assert_eq!((e.probe().2, e.rate() as u32), want);
        }
    }
}
