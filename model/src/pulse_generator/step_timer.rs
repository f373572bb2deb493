//! The output timing state machine of one axis: the queue of commanded
//! steps and the timers that space S1 and S2.

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
