//! The HDL's register snapshots (`motionhdl_hdl::probe`) as the model's
//! state types, so checks compare the two twins field by field. This is
//! the one place that knows both sides.

use motionhdl_hdl::probe::{
    ChannelRegisters, FilterRegisters, GeneratorRegisters, MoveEngineRegisters, StepTimerRegisters,
};
use motionhdl_model::counter::{ChannelState, InputFilter};
use motionhdl_model::pulse_generator::{
    MoveEngineProbe, PulseGenerator, Request, StepTimer, StepTimerState, PENDING_BITS, TIMER_BITS,
};

pub fn filter(r: FilterRegisters) -> InputFilter {
    InputFilter {
        s1: r.s1,
        s2: r.s2,
        level: r.level,
        cnt: r.cnt,
    }
}

pub fn step_timer(r: StepTimerRegisters) -> StepTimerState {
    StepTimerState {
        pending: r.pending,
        step: r.step,
        dir: r.dir,
        t_step: r.t_step,
        t_dir: r.t_dir,
        space_ok: r.space_ok,
        setup_ok: r.setup_ok,
        len_ok: r.len_ok,
        hold_ok: r.hold_ok,
        emitted: r.emitted,
    }
}

/// A pulse generator as the model's axis (full-width queue and timers).
pub fn generator(r: GeneratorRegisters) -> PulseGenerator {
    let mut timer = StepTimer::new(PENDING_BITS, TIMER_BITS);
    timer.set_state(step_timer(r.timer));
    PulseGenerator {
        phase: r.phase,
        position: r.position,
        command: match r.command {
            1 => Request::Up,
            -1 => Request::Down,
            _ => Request::None,
        },
        timer,
    }
}

pub fn channel(r: ChannelRegisters) -> ChannelState {
    ChannelState {
        fa: filter(r.fa),
        fb: filter(r.fb),
        fz: filter(r.fz),
        a_prev: r.a_prev,
        b_prev: r.b_prev,
        zg_prev: r.zg_prev,
        zg_q: r.zg_q,
        err_q: r.err_q,
        up_q: r.up_q,
        down_q: r.down_q,
        count: r.count,
        load_q: r.load_q,
        index_latch_q: r.index_latch_q,
        index_clear_q: r.index_clear_q,
        index: r.index,
        err: r.err,
        err_count: r.err_count,
        seen: r.seen,
        armed: r.armed,
        ctrl: r.ctrl,
        snap_count: r.snap_count,
        snap_index: r.snap_index,
        snap_status: r.snap_status,
    }
}

pub fn engine(r: MoveEngineRegisters) -> MoveEngineProbe {
    MoveEngineProbe {
        active: r.active,
        rate: r.rate,
        accel: r.accel,
        jerk: r.jerk,
        remaining: r.remaining,
        done: r.done,
        overflow: r.overflow,
        level: r.level,
        staged: r.staged,
        fetch: r.fetch,
        braking: r.braking,
    }
}
