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
///
/// The timing comparisons are made a clock ahead and held in flip-flops
/// (`space_ok`, `setup_ok`, `len_ok`, `hold_ok`), so no comparison sits
/// between a register and the queue's adder: each flag at clock k says
/// whether its timer's value at clock k reaches the timing of clock k-1.
/// A new STEP_TIMING/DIR_TIMING therefore acts one clock after it arrives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct StepTimerState {
    /// Commanded minus emitted steps, a step counting as emitted from the
    /// clock after S1 rose (see `emitted`).
    pub pending: i32,
    /// S1.
    pub step: bool,
    /// S2: 1 = negative direction (the counter bank's PULSE_DIR convention).
    pub dir: bool,
    /// Clocks S1 will have held its level at the next clock: 2 in the first
    /// clock after the edge that changed it; saturates at the timer's
    /// maximum.
    pub t_step: u32,
    /// The same for S2.
    pub t_dir: u32,
    /// S1 has been low for at least STEP_SPACE clocks.
    pub space_ok: bool,
    /// S2 has been stable for at least DIR_SETUP clocks.
    pub setup_ok: bool,
    /// S1 has been high for at least STEP_LEN clocks.
    pub len_ok: bool,
    /// S1 has been low for at least DIR_HOLD clocks.
    pub hold_ok: bool,
    /// S1 rose at the last edge: the step leaves the queue (and enters the
    /// position) at the next one, in the direction S2 shows.
    pub emitted: bool,
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
            (3..=16).contains(&pending_bits),
            "pending_bits = {pending_bits} out of range 3..=16"
        );
        assert!(
            (1..=16).contains(&timer_bits),
            "timer_bits = {timer_bits} out of range 1..=16"
        );
        let max = (1 << timer_bits) - 1;
        Self {
            pending_bits,
            timer_bits,
            state: Self::reset_state(max),
        }
    }

    fn reset_state(timer_max: u32) -> StepTimerState {
        StepTimerState {
            pending: 0,
            step: false,
            dir: false,
            t_step: timer_max,
            t_dir: timer_max,
            space_ok: true,
            setup_ok: true,
            len_ok: true,
            hold_ok: true,
            emitted: false,
        }
    }

    /// Largest queue magnitude: a request past it is refused.
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
        self.state = Self::reset_state(self.timer_max());
    }

    /// Whether the queue can take `request` at this edge.
    pub fn accepts(&self, request: Request) -> bool {
        match request {
            Request::None => true,
            Request::Up => self.state.pending < self.pending_max(),
            Request::Down => self.state.pending > -self.pending_max(),
        }
    }

    /// Whether a request in this direction decided now, and so reaching
    /// the queue one clock later, still fits: the queue is at least two
    /// steps from its end (one more may be on its way in).
    pub fn has_room(&self, request: Request) -> bool {
        match request {
            Request::None => true,
            Request::Up => self.state.pending <= self.pending_max() - 2,
            Request::Down => self.state.pending >= 2 - self.pending_max(),
        }
    }

    /// The step S1 starts at this edge, if any: +1 or -1.
    pub fn emits(&self) -> i32 {
        let s = &self.state;
        let want_negative = s.pending < 0;
        if !s.step && s.pending != 0 && s.dir == want_negative && s.space_ok && s.setup_ok {
            if s.dir {
                -1
            } else {
                1
            }
        } else {
            0
        }
    }

    /// The step that leaves the queue at this edge (S1 rose at the last
    /// one): +1, -1 or 0.
    pub fn leaving(&self) -> i32 {
        match (self.state.emitted, self.state.dir) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => -1,
        }
    }

    /// One rising clock edge. `request` must be one [`StepTimer::accepts`].
    pub fn clock(&mut self, request: Request, timing: &StepTiming) {
        self.clock_flushing(request, timing, false);
    }

    /// One edge; with `flush` the queue empties (the request and the
    /// leaving step are dropped with it), no step starts and S2 does not
    /// turn. S1 already high falls after STEP_LEN as usual.
    pub fn clock_flushing(&mut self, request: Request, timing: &StepTiming, flush: bool) {
        assert!(
            self.accepts(request),
            "request {request:?} with pending {}",
            self.state.pending
        );
        let max = self.timer_max();
        let inc = |t: u32| if t < max { t + 1 } else { t };
        let s = self.state;
        let emit = if flush { 0 } else { self.emits() };
        let falls = s.step && s.len_ok;
        let turns = !flush
            && !s.step
            && emit == 0
            && s.pending != 0
            && s.dir != (s.pending < 0)
            && s.hold_ok;
        // The timers' values at the next clock, compared with this clock's
        // timing: the flags of the next clock.
        let step_now = if falls || emit != 0 { 1 } else { s.t_step };
        let dir_now = if turns { 1 } else { s.t_dir };
        let commanded = match request {
            Request::None => 0,
            Request::Up => 1,
            Request::Down => -1,
        };
        self.state = StepTimerState {
            pending: if flush {
                0
            } else {
                s.pending + commanded - self.leaving()
            },
            step: if s.step { !falls } else { emit != 0 },
            dir: s.dir != turns,
            t_step: inc(step_now),
            t_dir: inc(dir_now),
            space_ok: step_now >= timing.step_space,
            setup_ok: dir_now >= timing.dir_setup,
            len_ok: step_now >= timing.step_len,
            hold_ok: step_now >= timing.dir_hold,
            emitted: emit != 0,
        };
    }
}
