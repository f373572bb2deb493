//! The C API's calls, one per driver function.

use super::*;
use crate::card::{AxisConfig, AxisSample, Stream};
use crate::safety::{Causes, Input};
use motionhdl_firmware::homing::HomingParams;

/// Writes COUNTER.CH[channel].CTRL.
///
/// # Safety
///
/// `card` is null or a card `motionhdl_init` filled (as for every call).
#[no_mangle]
pub unsafe extern "C" fn motionhdl_counter_configure(
    card: *mut MotionhdlCard,
    channel: u32,
    ctrl: u32,
) -> i32 {
    unsafe { with_card(card, |c| status(c.counter_configure(channel, ctrl))) }
}

/// Sets a channel's count (PRESET, then CMD.LOAD).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_counter_load(
    card: *mut MotionhdlCard,
    channel: u32,
    value: i32,
) -> i32 {
    unsafe { with_card(card, |c| status(c.counter_load(channel, value))) }
}

/// Writes COUNTER.CH[channel].CMD.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_counter_command(
    card: *mut MotionhdlCard,
    channel: u32,
    cmd: u32,
) -> i32 {
    unsafe { with_card(card, |c| status(c.counter_command(channel, cmd))) }
}

/// SNAPSHOT, then axes 0..n-1 into `out[0..n]` (n at most
/// `motionhdl_driver_axes()`): every value from the same clock.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `out` is null or has room for n.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_sample(
    card: *mut MotionhdlCard,
    out: *mut AxisSample,
    n: u32,
) -> i32 {
    if out.is_null() {
        return MOTIONHDL_ERR_ARGUMENT;
    }
    // SAFETY: the caller's contract on `out`.
    let out = unsafe { core::slice::from_raw_parts_mut(out, n as usize) };
    unsafe { with_card(card, |c| status(c.sample(out))) }
}

/// Sets an axis up for segment moves (mode, step and direction timing,
/// FIFO low-water mark, stop deceleration).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `config` is null or valid.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_axis_configure(
    card: *mut MotionhdlCard,
    axis: u32,
    config: *const AxisConfig,
) -> i32 {
    unsafe { given(card, config, |c, cfg| c.axis_configure(axis, cfg)) }
}

/// PULSE.AX[axis].STATUS into `*out`.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_axis_status(
    card: *mut MotionhdlCard,
    axis: u32,
    out: *mut u32,
) -> i32 {
    unsafe { fetch(card, out, |c| c.axis_status(axis)) }
}

/// `MOTIONHDL_OK` once the axis's move is out (STATUS.DONE and not BUSY),
/// `MOTIONHDL_BUSY` before.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_move_done(card: *mut MotionhdlCard, axis: u32) -> i32 {
    unsafe {
        with_card(card, |c| match c.move_done(axis) {
            Ok(true) => MOTIONHDL_OK,
            Ok(false) => MOTIONHDL_BUSY,
            Err(e) => e.code(),
        })
    }
}

/// Pushes one segment (SEG_STEPS, SEG_RATE, SEG_ACCEL, SEG_JERK, SEG_PUSH).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `segment` is null or valid.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_push_segment(
    card: *mut MotionhdlCard,
    axis: u32,
    segment: *const MotionhdlSegment,
) -> i32 {
    unsafe { given(card, segment, |c, s| c.push_segment(axis, &(*s).into())) }
}

/// Starts streaming a move into `axis`'s FIFO.
///
/// # Safety
///
/// `stream` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_stream_init(stream: *mut Stream, axis: u32) -> i32 {
    // SAFETY: the caller's contract.
    match unsafe { stream.as_mut() } {
        Some(s) if axis < crate::AXES => {
            *s = Stream::new(axis);
            MOTIONHDL_OK
        }
        _ => MOTIONHDL_ERR_ARGUMENT,
    }
}

/// Tops the FIFO up from `segments[stream->next..n]`: `MOTIONHDL_OK` once
/// all n are pushed, `MOTIONHDL_BUSY` while some are left (call again from
/// the main loop or the FIFO-low interrupt), `MOTIONHDL_ERR_FIFO_OVERFLOW`
/// if the FIFO lost a segment.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `stream` null or valid,
/// `segments` null or n readable segments.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_stream_refill(
    card: *mut MotionhdlCard,
    stream: *mut Stream,
    segments: *const MotionhdlSegment,
    n: u32,
) -> i32 {
    // SAFETY: the caller's contract.
    let (Some(s), false) = (unsafe { stream.as_mut() }, segments.is_null()) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    // SAFETY: the caller's contract.
    let segs = unsafe { core::slice::from_raw_parts(segments, n as usize) };
    unsafe {
        with_card(card, |c| match s.refill(c, segs) {
            Ok(true) => MOTIONHDL_OK,
            Ok(false) => MOTIONHDL_BUSY,
            Err(e) => e.code(),
        })
    }
}

/// Starts the axes in `mask` in the same clock (one PULSE.RUN write).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_start(card: *mut MotionhdlCard, mask: u32) -> i32 {
    unsafe { with_card(card, |c| status(c.start(mask))) }
}

/// Stops the axes in `mask` (steps already commanded still go out).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_stop(card: *mut MotionhdlCard, mask: u32) -> i32 {
    unsafe { with_card(card, |c| status(c.stop(mask))) }
}

/// SAFETY.STATUS into `*out` (ESTOP_INPUT, ESTOP, BITTEN, ARMED, IRQ).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_safety_status(card: *mut MotionhdlCard, out: *mut u32) -> i32 {
    unsafe { fetch(card, out, |c| Ok(c.safety_status())) }
}

/// Releases the e-stop latch and the watchdog's bite flag (the card is
/// halted from reset until this is done); `MOTIONHDL_ERR_ESTOP_INPUT`
/// while the e-stop input asks for a stop. Drives stay off until
/// `motionhdl_enable_drives`.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_clear_halt(card: *mut MotionhdlCard) -> i32 {
    unsafe { with_card(card, |c| status(c.clear_halt())) }
}

/// SAFETY.ENABLE: drive ENABLE outputs, bit n = axis n.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_enable_drives(card: *mut MotionhdlCard, mask: u32) -> i32 {
    unsafe { with_card(card, |c| status(c.enable_drives(mask))) }
}

/// Arms the watchdog to bite `clocks` + 1 clocks after this or the last
/// feed (0 disarms).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_watchdog_arm(card: *mut MotionhdlCard, clocks: u32) -> i32 {
    unsafe {
        with_card(card, |c| {
            c.watchdog_arm(clocks);
            MOTIONHDL_OK
        })
    }
}

/// Feeds the watchdog.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_watchdog_feed(card: *mut MotionhdlCard) -> i32 {
    unsafe {
        with_card(card, |c| {
            c.watchdog_feed();
            MOTIONHDL_OK
        })
    }
}

/// Turns a machine input on for the axes in `enable` (0: LIMIT_POS,
/// 1: LIMIT_NEG, 2: HOME, 3: ALARM), active low for those in `active_low`.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_input_configure(
    card: *mut MotionhdlCard,
    input: u32,
    enable: u32,
    active_low: u32,
) -> i32 {
    let input = match input {
        0 => Input::LimitPos,
        1 => Input::LimitNeg,
        2 => Input::Home,
        3 => Input::Alarm,
        _ => return MOTIONHDL_ERR_ARGUMENT,
    };
    unsafe {
        with_card(card, |c| {
            status(c.input_configure(input, enable, active_low))
        })
    }
}

/// Reads every interrupt cause register into `*out`.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_causes(card: *mut MotionhdlCard, out: *mut Causes) -> i32 {
    unsafe { fetch(card, out, |c| Ok(c.causes())) }
}

/// Clears the causes set in `*causes` (write 1 to clear).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `causes` is null or valid.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_clear_causes(
    card: *mut MotionhdlCard,
    causes: *const Causes,
) -> i32 {
    unsafe {
        given(card, causes, |c, causes| {
            c.clear_causes(causes);
            Ok(())
        })
    }
}

/// Which causes drive the IRQ pin (`*masks`, one word per cause register)
/// and its polarity (nonzero `active_high`).
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `masks` is null or valid.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_irq_configure(
    card: *mut MotionhdlCard,
    masks: *const Causes,
    active_high: u32,
) -> i32 {
    unsafe {
        given(card, masks, |c, masks| {
            c.irq_configure(masks, active_high != 0);
            Ok(())
        })
    }
}

/// Checks `*params` and starts a homing sequence in `*homing`.
///
/// # Safety
///
/// `homing` is null or writable; `params` is null or valid.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_home_start(
    homing: *mut MotionhdlHoming,
    params: *const MotionhdlHomingParams,
) -> i32 {
    // SAFETY: the caller's contract.
    let (Some(h), Some(p)) = (unsafe { homing.as_mut() }, unsafe { params.as_ref() }) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    let params = HomingParams {
        toward: p.toward,
        fast_period: p.fast_period,
        slow_period: p.slow_period,
        max_travel: p.max_travel,
        backoff: p.backoff,
        index: p.index != 0,
    };
    let Ok(seq) = Homing::new(params) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    h.started = 0;
    // SAFETY: the storage is large and aligned enough (asserted above).
    unsafe { core::ptr::write(h.storage.as_mut_ptr().cast::<Homing>(), seq) };
    h.started = 1;
    MOTIONHDL_OK
}

/// One step of the homing sequence on `axis`: `MOTIONHDL_BUSY` while it
/// runs, `MOTIONHDL_OK` with `*home` filled once found, or
/// `MOTIONHDL_ERR_HOME_*`. Never blocks.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `homing` is null or started with
/// `motionhdl_home_start`; `home` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_home_poll(
    card: *mut MotionhdlCard,
    homing: *mut MotionhdlHoming,
    axis: u32,
    home: *mut MotionhdlHome,
) -> i32 {
    // SAFETY: the caller's contract.
    let (Some(h), Some(out)) = (unsafe { homing.as_mut() }, unsafe { home.as_mut() }) else {
        return MOTIONHDL_ERR_ARGUMENT;
    };
    if h.started == 0 {
        return MOTIONHDL_ERR_ARGUMENT;
    }
    // SAFETY: `started` says `motionhdl_home_start` wrote a Homing there.
    let seq = unsafe { &mut *h.storage.as_mut_ptr().cast::<Homing>() };
    unsafe {
        with_card(card, |c| match c.home_poll(seq, axis) {
            Ok(None) => MOTIONHDL_BUSY,
            Ok(Some(found)) => {
                *out = MotionhdlHome {
                    position: found.position,
                    count: found.count,
                    index: found.index.unwrap_or(0),
                    has_index: u32::from(found.index.is_some()),
                };
                MOTIONHDL_OK
            }
            Err(e) => e.code(),
        })
    }
}

/// Writes n words into the shared RAM from word `word` on.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `data` is null or n readable words.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_ram_write(
    card: *mut MotionhdlCard,
    word: u32,
    data: *const u16,
    n: u32,
) -> i32 {
    if data.is_null() {
        return MOTIONHDL_ERR_ARGUMENT;
    }
    // SAFETY: the caller's contract.
    let data = unsafe { core::slice::from_raw_parts(data, n as usize) };
    unsafe { with_card(card, |c| status(c.ram_write(word, data))) }
}

/// Reads n words of the shared RAM from word `word` on.
///
/// # Safety
///
/// As for `motionhdl_counter_configure`; `data` is null or n writable words.
#[no_mangle]
pub unsafe extern "C" fn motionhdl_ram_read(
    card: *mut MotionhdlCard,
    word: u32,
    data: *mut u16,
    n: u32,
) -> i32 {
    if data.is_null() {
        return MOTIONHDL_ERR_ARGUMENT;
    }
    // SAFETY: the caller's contract.
    let data = unsafe { core::slice::from_raw_parts_mut(data, n as usize) };
    unsafe { with_card(card, |c| status(c.ram_read(word, data))) }
}
