//! Step/pulse generator of one axis (docs/pulse_generator.md): an NCO that
//! commands steps, a signed queue of commanded-but-not-yet-emitted steps, and
//! the output timing state machine that emits them as S1 (step) and S2
//! (direction) with minimum step length, step space, direction set-up and
//! direction hold. A step that would violate a timing waits in the queue; no
//! step is ever dropped.
//!
//! One file per part, as the HDL has them (`hdl/src/step_timer.rs`,
//! `move_engine.rs`, `pulse_bank.rs`): `step_timer` (the output timing
//! state machine), `move_engine` (the segment FIFO) and `pulse_bank` (the
//! axes behind the register bus); the axis itself is here.

#[cfg(test)]
mod axis_tests;
mod move_engine;
#[cfg(test)]
mod move_tests;
mod pulse_bank;
mod step_timer;
#[cfg(test)]
mod tests;

pub use motionhdl_spec::pulse::{
    Segment, ACCEL_FRAC_BITS, JERK_FRAC_BITS, LOAD_FRACTION, PENDING_BITS, RAMP_BITS,
    SEGMENT_FIFO_DEPTH, TIMER_BITS,
};
pub use move_engine::{MoveEngine, MoveEngineProbe, SegmentField, SEGMENT_FETCH_CLOCKS};
pub use pulse_bank::{quadrature, PulseBank, Stops};
pub use step_timer::{Request, StepTimer, StepTimerState, StepTiming};

/// The whole axis: NCO, step timer and position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PulseGenerator {
    /// NCO phase accumulator.
    pub phase: u32,
    /// Emitted steps, signed, modulo 2^32: a step counts from the clock
    /// after S1 rose.
    pub position: u32,
    /// The step the NCO commanded at the last edge, on its way into the
    /// queue (a register: the NCO's carry chain ends there).
    pub command: Request,
    pub timer: StepTimer,
}

/// One clock's inputs of the axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PulseInputs {
    /// The NCO runs; without it, queued steps still go out.
    pub enable: bool,
    /// Stop now (the safety block's HALT): the NCO holds, queued steps are
    /// dropped, and from this edge S1 starts no step and S2 does not turn
    /// (a step already high still ends after STEP_LEN).
    pub halt: bool,
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
            command: Request::None,
            timer: StepTimer::new(PENDING_BITS, TIMER_BITS),
        }
    }

    /// S1 and S2.
    pub fn outputs(&self) -> (bool, bool) {
        let s = self.timer.state();
        (s.step, s.dir)
    }

    /// STATUS.BUSY: a step is commanded and not yet out (on its way into
    /// the queue, queued, or leaving it) or S1 is high.
    pub fn busy(&self) -> bool {
        let s = self.timer.state();
        s.pending != 0 || s.step || self.command != Request::None
    }

    /// The NCO's request at this edge, and whether the queue holds it back
    /// (then the phase does not advance either).
    pub fn request(&self, inp: &PulseInputs) -> (Request, bool) {
        if !inp.enable || inp.halt {
            return (Request::None, false);
        }
        let sum = u64::from(self.phase) + u64::from(inp.rate.unsigned_abs());
        let request = match (sum >> 32 != 0, inp.rate < 0) {
            (false, _) => Request::None,
            (true, false) => Request::Up,
            (true, true) => Request::Down,
        };
        let blocked = !self.timer.has_room(if inp.rate < 0 {
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
        if inp.enable && !inp.halt && !blocked {
            self.phase = self.phase.wrapping_add(inp.rate.unsigned_abs());
        }
        self.position = self.position.wrapping_add(self.timer.leaving() as u32);
        self.timer
            .clock_flushing(self.command, &inp.timing, inp.halt);
        self.command = request;
    }
}
