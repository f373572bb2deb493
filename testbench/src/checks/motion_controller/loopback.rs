//! The top with its pulse outputs wired back to its encoder inputs,
//! through the FSMC pins: the dual-CPU seed's closed loop, and segment
//! moves counted back.

use super::{loopback_board, play, run_top};
use crate::bfm::fsmc::{Observation, Op};
use crate::verilog_sim::Target;
use motionhdl_hdl::MotionController;
use motionhdl_model::regmap::{self};
use motionhdl_model::Config;

/// The dual-CPU seed's closed loop on the whole top in the generated
/// Verilog: every axis's pulse outputs wired back to its encoder inputs
/// (A = F1, B = F2) in the testbench, configured and run through the FSMC
/// BFM: axes 0 and 1 pulse+direction (counted PULSE_DIR), axis 2 CW/CCW
/// (counted CW_CCW), axis 3 quadrature (counted X4), rates of both signs
/// with a reversal; then RUN off, SNAPSHOT, and COUNT and POSITION of every
/// axis read over the bus. Returns (COUNT, POSITION) per axis.
pub fn loopback_verilog(
    target: impl Into<Target>,
    config: &Config,
) -> Result<Vec<(i32, i32)>, String> {
    let ops = loopback_ops(config);
    loopback_results(config.axes(), &play(target.into(), config, &ops, true)?)
}

/// The same loop in rust-hdl (default 4 axes, internal RAM).
pub fn loopback_rust(config: &Config) -> Result<Vec<(i32, i32)>, String> {
    let ops = loopback_ops(config);
    let (obs, _) = run_top(MotionController::<4>::new(config), &ops, loopback_board);
    loopback_results(config.axes(), &obs)
}

fn loopback_results(n: u32, obs: &[Observation]) -> Result<Vec<(i32, i32)>, String> {
    if obs.len() != 4 * n as usize {
        return Err(format!("{} reads, expected {}", obs.len(), 4 * n));
    }
    let word =
        |k: usize| (u32::from(obs[k].data_end) | u32::from(obs[k + 1].data_end) << 16) as i32;
    Ok((0..n as usize)
        .map(|i| (word(4 * i), word(4 * i + 2)))
        .collect())
}

/// The loopback's FSMC ops: configure, run with a reversal per axis, stop,
/// SNAPSHOT, then COUNT and POSITION of every axis.
pub fn loopback_ops(config: &Config) -> Vec<Op> {
    use motionhdl_model::regmap::mode;
    let map = regmap::mcu_map(config);
    let counter = map.block("COUNTER");
    let pulse = map.block("PULSE");
    let (ch, ax) = (counter.array("CH"), pulse.array("AX"));
    let n = config.axes();
    let w = |word: u32, data: u32| Op::Write32 {
        a: (word * 2) as u16,
        data,
    };
    // Reset sets the e-stop latch; the chain is closed, so release it.
    let safety = map.block("SAFETY");
    let mut ops = vec![
        Op::Reset,
        w(safety.base + safety.register("CLEAR").offset, 1),
    ];
    for i in 0..n {
        let (counter_mode, pulse_ctrl) = match i % 4 {
            0 | 1 => (mode::PULSE_DIR, 0),
            2 => (mode::CW_CCW, 1),
            _ => (mode::X4, 2),
        };
        ops.push(w(counter.base + ch.address(i, "CTRL"), counter_mode));
        ops.push(w(pulse.base + ax.address(i, "CTRL"), pulse_ctrl));
        ops.push(w(
            pulse.base + ax.address(i, "STEP_TIMING"),
            (1 + i % 3) | (1 + i % 2) << 16,
        ));
        ops.push(w(pulse.base + ax.address(i, "DIR_TIMING"), 2 | 2 << 16));
        let rate = 0x1000_0000 * if i % 2 == 0 { 1 } else { -1 };
        ops.push(w(pulse.base + ax.address(i, "RATE"), rate as u32));
    }
    let run = pulse.base + pulse.register("RUN").offset;
    ops.push(w(run, (1 << n) - 1));
    ops.push(Op::Idle { hclk: 3000 });
    for i in 0..n {
        // Reverse every axis at a different moment.
        let rate = -0x0400_0000 * if i % 2 == 0 { 1 } else { -1 };
        ops.push(w(pulse.base + ax.address(i, "RATE"), rate as u32));
        ops.push(Op::Idle { hclk: 200 });
    }
    ops.push(Op::Idle { hclk: 3000 });
    ops.push(w(run, 0));
    ops.push(Op::Idle { hclk: 500 });
    ops.push(w(counter.base + counter.register("SNAPSHOT").offset, 0));
    for i in 0..n {
        ops.push(Op::Read32 {
            a: ((counter.base + ch.address(i, "COUNT")) * 2) as u16,
        });
        ops.push(Op::Read32 {
            a: ((pulse.base + ax.address(i, "POSITION")) * 2) as u16,
        });
    }
    ops
}

/// Segments of [`moves_ops`]: accelerate, cruise, decelerate, and one
/// back (steps, start rate, SEG_ACCEL: 2^-16 rate LSBs per clock).
pub const MOVE_SEGMENTS: [(u32, i32, i32); 4] = [
    (30, 1 << 24, 1 << 30),
    (60, 1 << 28, 0),
    (30, 1 << 28, -(1 << 28)),
    (25, -(1 << 27), 0),
];

/// A position move through axis 0's segment FIFO (MOVES mode), counted by
/// channel 0 in pulse+direction through the pin loopback: stream the four
/// [`MOVE_SEGMENTS`] through the FIFO around RUN, wait, then
/// STATUS (DONE, no OVERFLOW), SNAPSHOT, COUNT and POSITION.
pub fn moves_ops(config: &Config) -> Vec<Op> {
    use motionhdl_model::regmap::mode;
    let map = regmap::mcu_map(config);
    let counter = map.block("COUNTER");
    let pulse = map.block("PULSE");
    let (ch, ax) = (counter.array("CH"), pulse.array("AX"));
    let w = |word: u32, data: u32| Op::Write32 {
        a: (word * 2) as u16,
        data,
    };
    let r = |word: u32| Op::Read32 {
        a: (word * 2) as u16,
    };
    let safety = map.block("SAFETY");
    let mut ops = vec![
        Op::Reset,
        w(safety.base + safety.register("CLEAR").offset, 1),
        w(counter.base + ch.address(0, "CTRL"), mode::PULSE_DIR),
        w(pulse.base + ax.address(0, "CTRL"), 0b100),
        w(pulse.base + ax.address(0, "STEP_TIMING"), 2 | 2 << 16),
        w(pulse.base + ax.address(0, "DIR_TIMING"), 3 | 3 << 16),
    ];
    let push = |ops: &mut Vec<Op>, (steps, rate, accel): (u32, i32, i32)| {
        ops.push(w(pulse.base + ax.address(0, "SEG_STEPS"), steps));
        ops.push(w(pulse.base + ax.address(0, "SEG_RATE"), rate as u32));
        ops.push(w(pulse.base + ax.address(0, "SEG_ACCEL"), accel as u32));
        ops.push(w(pulse.base + ax.address(0, "SEG_JERK"), 0));
        ops.push(w(pulse.base + ax.address(0, "SEG_PUSH"), 0));
    };
    // Push two, start, and push the rest as the firmware would stream
    // them (the FIFO holds 64); the move (about 5300 clocks) is over well
    // within the nine 4000-HCLK (1190-clock) waits.
    let [s0, s1, s2, s3] = MOVE_SEGMENTS;
    push(&mut ops, s0);
    push(&mut ops, s1);
    ops.push(w(pulse.base + pulse.register("RUN").offset, 1));
    push(&mut ops, s2);
    ops.push(Op::Idle { hclk: 4000 });
    push(&mut ops, s3);
    for _ in 0..8 {
        ops.push(Op::Idle { hclk: 4000 });
    }
    ops.push(r(pulse.base + ax.address(0, "STATUS")));
    ops.push(w(counter.base + counter.register("SNAPSHOT").offset, 0));
    ops.push(r(counter.base + ch.address(0, "COUNT")));
    ops.push(r(pulse.base + ax.address(0, "POSITION")));
    ops
}

/// (STATUS, COUNT, POSITION) the reads of [`moves_ops`] returned.
fn moves_results(obs: &[Observation]) -> Result<(u32, i32, i32), String> {
    if obs.len() != 6 {
        return Err(format!("{} reads, expected 6", obs.len()));
    }
    let word = |k: usize| u32::from(obs[k].data_end) | u32::from(obs[k + 1].data_end) << 16;
    Ok((word(0), word(2) as i32, word(4) as i32))
}

/// [`moves_ops`] in rust-hdl with the pin loopback.
pub fn moves_rust(config: &Config) -> Result<(u32, i32, i32), String> {
    let (obs, _) = run_top(
        MotionController::<4>::new(config),
        &moves_ops(config),
        loopback_board,
    );
    moves_results(&obs)
}

/// [`moves_ops`] in the generated Verilog with the pin loopback.
pub fn moves_verilog(
    target: impl Into<Target>,
    config: &Config,
) -> Result<(u32, i32, i32), String> {
    moves_results(&play(target.into(), config, &moves_ops(config), true)?)
}
