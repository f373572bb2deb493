//! The homing sequence against a simulated axis that behaves as the
//! gateware documents (stop on the switch's edge with HOME_STOP, capture at
//! that edge, a one-shot index latch); the whole-controller scenario
//! (`testbench/tests/homing.rs`) runs it against the HDL.

use motionhdl_firmware::homing::{Home, Homing, HomingAxis, HomingError, HomingParams, Poll};

/// One axis: a shaft position, a switch active at or beyond `switch`
/// (the positive side), index pulses every `index_every` steps.
struct Axis {
    position: i32,
    switch: i32,
    index_every: Option<i32>,
    home_on: bool,
    home_stop: bool,
    cause: bool,
    before: bool,
    captured: (i32, i32),
    target: i32,
    period: u32,
    index_armed: bool,
    index: Option<i32>,
    /// Every move started: (steps, period).
    moves: Vec<(i32, u32)>,
    /// The switch goes away (a loose cam) as move n starts.
    lose_switch_at_move: Option<usize>,
}

impl Axis {
    fn new(position: i32, switch: i32) -> Self {
        Self {
            position,
            switch,
            index_every: None,
            home_on: false,
            home_stop: false,
            cause: false,
            before: false,
            captured: (0, 0),
            target: position,
            period: 1,
            index_armed: false,
            index: None,
            moves: Vec::new(),
            lose_switch_at_move: None,
        }
    }

    fn active(&self) -> bool {
        self.position >= self.switch
    }

    /// The gateware's edge detector: the cause sets where HOME starts
    /// acting; with HOME_STOP the move ends there.
    fn sample(&mut self) {
        let acting = self.home_on && self.active();
        if acting && !self.before {
            self.cause = true;
            self.captured = (self.position, self.position * 4);
            if self.home_stop {
                self.target = self.position;
            }
        }
        self.before = acting;
    }

    /// One poll's worth of time: a fast move covers 8 steps, a slow one 1.
    fn advance(&mut self) {
        let steps = if self.period < 100 { 8 } else { 1 };
        for _ in 0..steps {
            if self.position == self.target || (self.cause && self.home_stop) {
                return;
            }
            self.position += (self.target - self.position).signum();
            if let (Some(every), true) = (self.index_every, self.index_armed) {
                if self.position.rem_euclid(every) == 0 {
                    self.index = Some(self.position * 4);
                    self.index_armed = false;
                }
            }
            self.sample();
        }
    }
}

impl HomingAxis for Axis {
    fn arm_home(&mut self) {
        self.home_on = true;
        self.home_stop = true;
        self.sample();
    }
    fn release_home(&mut self) {
        self.home_stop = false;
    }
    fn start_move(&mut self, steps: i32, period: u32) {
        assert!(
            !(self.cause && self.home_stop),
            "a move while the cause stops the axis"
        );
        self.target = self.position + steps;
        self.period = period;
        self.moves.push((steps, period));
        if self.lose_switch_at_move == Some(self.moves.len()) {
            self.switch = i32::MAX;
        }
    }
    fn stop(&mut self) {
        self.target = self.position;
    }
    fn moving(&mut self) -> bool {
        self.advance();
        self.position != self.target && !(self.cause && self.home_stop)
    }
    fn home_seen(&mut self) -> bool {
        self.cause
    }
    fn clear_home(&mut self) {
        self.cause = false;
    }
    fn on_switch(&mut self) -> bool {
        self.active()
    }
    fn captured(&mut self) -> (i32, i32) {
        self.captured
    }
    fn arm_index(&mut self) {
        self.index_armed = true;
        self.index = None;
    }
    fn index(&mut self) -> Option<i32> {
        self.index
    }
}

fn params(index: bool) -> HomingParams {
    HomingParams {
        toward: 1,
        fast_period: 50,
        slow_period: 500,
        max_travel: 1_000,
        backoff: 20,
        index,
    }
}

fn home(axis: &mut Axis, p: HomingParams) -> Poll {
    let mut homing = Homing::new(p).expect("valid parameters");
    for _ in 0..10_000 {
        match homing.poll(axis) {
            Poll::Busy => continue,
            done => return done,
        }
    }
    panic!("homing did not finish");
}

#[test]
fn finds_the_switch_from_below_and_captures_its_edge() {
    for start in [-500, 0, 299] {
        let mut axis = Axis::new(start, 300);
        let got = home(&mut axis, params(false));
        let want = Home {
            position: 300,
            count: 1_200,
            index: None,
        };
        assert_eq!(got, Poll::Done(want), "start {start}");
        // Fast search over the travel, back-off, slow search over twice
        // the back-off.
        let want = [(1_000, 50), (-20, 50), (40, 500)];
        assert_eq!(axis.moves, want, "start {start}");
    }
}

#[test]
fn starting_on_the_switch_backs_off_first() {
    for start in [300, 310, 345] {
        let mut axis = Axis::new(start, 300);
        let got = home(&mut axis, params(false));
        assert!(
            matches!(got, Poll::Done(h) if h.position == 300),
            "start {start}: {got:?}"
        );
        // Back-offs of 20 until off the switch, then the slow search.
        let backoffs = ((start - 300) / 20 + 1) as usize;
        let mut want = vec![(-20, 50); backoffs];
        want.push((40, 500));
        assert_eq!(axis.moves, want, "start {start}");
    }
}

#[test]
fn the_index_search_finds_the_first_pulse_past_the_switch() {
    let mut axis = Axis::new(0, 300);
    axis.index_every = Some(64);
    let got = home(&mut axis, params(true));
    let want = Home {
        position: 300,
        count: 1_200,
        index: Some(320 * 4),
    };
    assert_eq!(got, Poll::Done(want));
    assert_eq!(axis.position, 320, "stops at the index");
    // On over the switch at the slow period, up to the whole travel.
    assert_eq!(axis.moves.last(), Some(&(1_000, 500)));
}

#[test]
fn failures_are_reported() {
    let mut far = Axis::new(0, 5_000);
    assert_eq!(
        home(&mut far, params(false)),
        Poll::Failed(HomingError::NotFound)
    );
    let mut no_index = Axis::new(0, 300);
    assert_eq!(
        home(&mut no_index, params(true)),
        Poll::Failed(HomingError::NoIndex)
    );
    // A switch gone by the slow search (the third move).
    let mut lost = Axis::new(0, 300);
    lost.lose_switch_at_move = Some(3);
    assert_eq!(
        home(&mut lost, params(false)),
        Poll::Failed(HomingError::Lost)
    );
    // A switch that stays active everywhere.
    let mut stuck = Axis::new(0, i32::MIN);
    assert_eq!(
        home(&mut stuck, params(false)),
        Poll::Failed(HomingError::StuckOnSwitch)
    );
    // It backed off the whole travel first: 1000 / 20 back-offs.
    assert_eq!(stuck.moves, vec![(-20, 50); 50]);
}

#[test]
fn bad_parameters_name_the_value_and_range() {
    let e = Homing::new(HomingParams {
        toward: 0,
        ..params(false)
    })
    .unwrap_err();
    assert_eq!((e.name, e.value, e.min, e.max), ("toward", 0, -1, 1));
    let e = Homing::new(HomingParams {
        backoff: 2_000,
        ..params(false)
    })
    .unwrap_err();
    assert_eq!((e.name, e.value, e.max), ("backoff", 2_000, 1_000));
    // Both directions are accepted.
    for toward in [-1, 1] {
        assert!(Homing::new(HomingParams {
            toward,
            ..params(false)
        })
        .is_ok());
    }
}
