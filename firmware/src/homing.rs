//! Homing one axis against its HOME switch, the sequence the STM32 + FPGA
//! seed's firmware runs: a fast search toward the switch, a back-off, a
//! slow search that the gateware captures, and optionally the first index
//! pulse after the switch (docs/safety_io.md, "Home capture").
//!
//! The gateware does the timing-critical part: with HOME_STOP set the axis
//! stops on the switch's filtered edge, and HOME_POSITION / HOME_COUNT hold
//! the commanded and counted position at that edge, so the result does not
//! depend on how fast the firmware polls. The firmware only sequences the
//! moves: [`Homing::poll`] never blocks, so it runs from a main loop or a
//! timer interrupt beside everything else. The register accesses go
//! through [`HomingAxis`], which a driver implements on the register map.

use crate::OutOfRange;

/// What the sequence needs from one axis of the FPGA: each method is one
/// or two register accesses (names from the generated register map).
pub trait HomingAxis {
    /// Turns the axis's HOME input on with stop on home: SAFETY.HOME_CTRL
    /// ENABLE and SAFETY.HOME_STOP set for the axis.
    fn arm_home(&mut self);
    /// Turns stop on home off again (HOME_STOP clear; the input stays on).
    fn release_home(&mut self);
    /// Starts a constant-rate move of `steps` steps (the sign is the
    /// direction) at one step per `period` clocks: one segment and RUN.
    fn start_move(&mut self, steps: i32, period: u32);
    /// Stops the axis (its RUN bit clear; the steps already commanded
    /// still go out).
    fn stop(&mut self);
    /// Whether the axis still moves (PULSE.AX.STATUS: a segment running,
    /// queued, or a step not yet out).
    fn moving(&mut self) -> bool;
    /// SAFETY.HOME_ALARM_CAUSE.HOME of the axis: the switch's edge was seen
    /// (the axis stopped on it and the capture registers hold it).
    fn home_seen(&mut self) -> bool;
    /// Clears SAFETY.HOME_ALARM_CAUSE.HOME (write 1): the axis may move.
    fn clear_home(&mut self);
    /// SAFETY.HOME_ALARM_INPUTS.HOME: the switch is active now.
    fn on_switch(&mut self) -> bool;
    /// PULSE.AX.HOME_POSITION and COUNTER.CH.HOME_COUNT.
    fn captured(&mut self) -> (i32, i32);
    /// Arms the counter channel's one-shot index latch (CTRL.IDX_LATCH and
    /// IDX_ONESHOT, CMD.ARM).
    fn arm_index(&mut self);
    /// The latched index count, once the armed latch has fired
    /// (SNAPSHOT, STATUS.ARMED clear, INDEX).
    fn index(&mut self) -> Option<i32>;
}

/// How to home.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HomingParams {
    /// +1: the switch is in the positive direction; −1: negative.
    pub toward: i32,
    /// Clocks per step of the fast search and the back-off.
    pub fast_period: u32,
    /// Clocks per step of the slow search and the index search.
    pub slow_period: u32,
    /// The longest search in steps: no switch within it is an error.
    pub max_travel: u32,
    /// Steps to back off the switch before the slow search.
    pub backoff: u32,
    /// Also find the first index pulse after the switch.
    pub index: bool,
}

impl HomingParams {
    /// Checks every parameter: `toward` ±1, periods 2..=2^24 clocks (the
    /// step timing needs at least 2), travel 1..=2^30, back-off
    /// 1..=travel.
    pub fn checked(self) -> Result<Self, OutOfRange> {
        if self.toward != 1 && self.toward != -1 {
            return Err(OutOfRange {
                name: "toward",
                value: i64::from(self.toward),
                min: -1,
                max: 1,
            });
        }
        OutOfRange::check("fast_period", self.fast_period.into(), 2, 1 << 24)?;
        OutOfRange::check("slow_period", self.slow_period.into(), 2, 1 << 24)?;
        OutOfRange::check("max_travel", self.max_travel.into(), 1, 1 << 30)?;
        OutOfRange::check("backoff", self.backoff.into(), 1, self.max_travel.into())?;
        Ok(self)
    }
}

/// Where home is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Home {
    /// POSITION at the switch's edge in the slow search.
    pub position: i32,
    /// The count at the same edge.
    pub count: i32,
    /// The count at the first index pulse after it (index homing).
    pub index: Option<i32>,
}

/// Why homing failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HomingError {
    /// The fast search ran `max_travel` steps without the switch.
    NotFound,
    /// Backing off `max_travel` steps did not leave the switch.
    StuckOnSwitch,
    /// The slow search passed the back-off distance twice without the
    /// switch (it moved, or the filter is longer than the back-off).
    Lost,
    /// No index pulse within `max_travel` steps after the switch.
    NoIndex,
}

/// What [`Homing::poll`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Poll {
    /// Still moving: poll again.
    Busy,
    Done(Home),
    Failed(HomingError),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Start,
    FastSearch,
    BackOff { backed: u32 },
    SlowSearch,
    IndexSearch { home: Home },
    Finished(Poll),
}

/// The sequence for one axis; see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Homing {
    params: HomingParams,
    phase: Phase,
}

impl Homing {
    pub fn new(params: HomingParams) -> Result<Self, OutOfRange> {
        Ok(Self {
            params: params.checked()?,
            phase: Phase::Start,
        })
    }

    /// Moves the sequence on as far as it can without waiting.
    pub fn poll<A: HomingAxis>(&mut self, axis: &mut A) -> Poll {
        let p = self.params;
        let travel = p.max_travel as i32;
        let backoff = p.backoff as i32;
        self.phase = match self.phase {
            Phase::Start => {
                axis.arm_home();
                let on_switch = axis.on_switch();
                // A stale cause, or (on the switch) the one enabling it set.
                axis.clear_home();
                if on_switch {
                    axis.start_move(-p.toward * backoff, p.fast_period);
                    Phase::BackOff { backed: p.backoff }
                } else {
                    axis.start_move(p.toward * travel, p.fast_period);
                    Phase::FastSearch
                }
            }
            Phase::IndexSearch { home } => match axis.index() {
                Some(index) => {
                    axis.stop();
                    Phase::Finished(Poll::Done(Home {
                        index: Some(index),
                        ..home
                    }))
                }
                None if axis.moving() => Phase::IndexSearch { home },
                None => Phase::Finished(Poll::Failed(HomingError::NoIndex)),
            },
            phase if axis.moving() => phase,
            Phase::FastSearch if axis.home_seen() => {
                axis.clear_home();
                axis.start_move(-p.toward * backoff, p.fast_period);
                Phase::BackOff { backed: p.backoff }
            }
            Phase::FastSearch => Phase::Finished(Poll::Failed(HomingError::NotFound)),
            Phase::BackOff { backed } if axis.on_switch() => {
                if backed >= p.max_travel {
                    Phase::Finished(Poll::Failed(HomingError::StuckOnSwitch))
                } else {
                    axis.start_move(-p.toward * backoff, p.fast_period);
                    Phase::BackOff {
                        backed: backed + p.backoff,
                    }
                }
            }
            Phase::BackOff { .. } => {
                axis.clear_home();
                axis.start_move(p.toward * 2 * backoff, p.slow_period);
                Phase::SlowSearch
            }
            Phase::SlowSearch if axis.home_seen() => {
                let (position, count) = axis.captured();
                let home = Home {
                    position,
                    count,
                    index: None,
                };
                if p.index {
                    // Move on over the switch to the next index pulse.
                    axis.release_home();
                    axis.clear_home();
                    axis.arm_index();
                    axis.start_move(p.toward * travel, p.slow_period);
                    Phase::IndexSearch { home }
                } else {
                    axis.release_home();
                    Phase::Finished(Poll::Done(home))
                }
            }
            Phase::SlowSearch => Phase::Finished(Poll::Failed(HomingError::Lost)),
            finished @ Phase::Finished(_) => finished,
        };
        match self.phase {
            Phase::Finished(poll) => poll,
            _ => Poll::Busy,
        }
    }
}
