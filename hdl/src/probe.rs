//! Snapshots of a block's flip-flops as plain values, for the testbench.
//! The testbench maps them onto the model's state types
//! (`testbench/src/state_map.rs`); the HDL knows nothing of the model.

/// One input filter: synchroniser, accepted level, countdown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FilterRegisters {
    pub s1: bool,
    pub s2: bool,
    pub level: bool,
    pub cnt: u8,
}

/// The step timer: pending queue (read as two's complement), S1, S2, the
/// two hold timers, the four timing flags and the step leaving the queue.
/// (The room flags are a function of the queue, checked as outputs.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepTimerRegisters {
    pub pending: i32,
    pub step: bool,
    pub dir: bool,
    pub t_step: u32,
    pub t_dir: u32,
    pub space_ok: bool,
    pub setup_ok: bool,
    pub len_ok: bool,
    pub hold_ok: bool,
    pub emitted: bool,
}

/// A pulse generator: NCO phase, position, the command register (+1, -1
/// or 0) and the step timer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GeneratorRegisters {
    pub phase: u32,
    pub position: u32,
    pub command: i8,
    pub timer: StepTimerRegisters,
}

/// Every register of one counter channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChannelRegisters {
    pub fa: FilterRegisters,
    pub fb: FilterRegisters,
    pub fz: FilterRegisters,
    pub a_prev: bool,
    pub b_prev: bool,
    pub zg_prev: bool,
    pub zg_q: bool,
    pub err_q: bool,
    pub up_q: bool,
    pub down_q: bool,
    pub count: u32,
    pub load_q: bool,
    pub index_latch_q: bool,
    pub index_clear_q: bool,
    pub index: u32,
    pub err: bool,
    pub err_count: u32,
    pub seen: bool,
    pub armed: bool,
    pub ctrl: u32,
    pub snap_count: u32,
    pub snap_index: u32,
    pub snap_status: u32,
}

/// The move engine: running segment, FIFO bookkeeping and the head copy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveEngineRegisters {
    pub active: bool,
    /// Rate and acceleration with their 16 fraction bits (48 bits).
    pub rate: u64,
    pub accel: u64,
    pub jerk: u32,
    pub remaining: u32,
    pub done: bool,
    pub overflow: bool,
    pub level: u32,
    pub staged: bool,
    pub fetch: u32,
    pub braking: bool,
}

/// The safety block's interrupt state: causes, masks and the polarity
/// (one bit per axis in the per-axis registers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SafetyRegisters {
    pub cause: u32,
    pub cause_mask: u32,
    pub done_cause: u32,
    pub done_mask: u32,
    pub low_cause: u32,
    pub low_mask: u32,
    pub active_high: bool,
    /// The machine inputs' filtered levels before polarity, in
    /// `MACHINE_INPUTS` order (bit i = axis i).
    pub levels: [u32; 4],
    /// LIMIT_POS_CTRL, LIMIT_NEG_CTRL, HOME_CTRL, ALARM_CTRL.
    pub input_ctrl: [u32; 4],
    pub limit_cause: u32,
    pub limit_mask: u32,
    pub home_alarm_cause: u32,
    pub home_alarm_mask: u32,
    /// The general-purpose I/O: filtered input levels, GPI_EDGE_CTRL,
    /// GPI_CAUSE, GPI_MASK, GPO_VALUE, GPO_SAFE, GPO_OPEN_DRAIN.
    pub gpio: [u32; 7],
    /// SOFT_LIMIT_CTRL, SOFT_LIMIT_CAUSE, SOFT_LIMIT_MASK.
    pub soft: [u32; 3],
    /// COUNTER_CAUSE, COUNTER_MASK (index 1 and 2; 0 unused).
    pub counter_events: [u32; 3],
}

impl SafetyRegisters {
    /// OR(cause AND mask) over every cause register.
    pub fn irq_active(&self) -> bool {
        self.cause & self.cause_mask != 0
            || self.done_cause & self.done_mask != 0
            || self.low_cause & self.low_mask != 0
            || self.limit_cause & self.limit_mask != 0
            || self.home_alarm_cause & self.home_alarm_mask != 0
            || self.gpio[2] & self.gpio[3] != 0
            || self.soft[1] & self.soft[2] != 0
            || self.counter_events[1] & self.counter_events[2] != 0
    }
}
