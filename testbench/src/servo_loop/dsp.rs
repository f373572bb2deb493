//! The DSP's firmware on the servo card, as the seed describes it: take
//! the PC's coarse points, refine them with the cubic B-spline, and per
//! servo tick run one incremental PID step per axis and stage the DAC
//! codes. The algorithms are the firmware crate's; this file is the loop
//! around them and its bus accesses.

use super::{ServoCard, AXES, CLOCK_S};
use motionhdl_firmware::bspline::{clamped, FineInterpolator};
use motionhdl_firmware::pid::{dac_offset_binary, IncrementalPid, PidGains};
use motionhdl_model::regmap::{mode, ISA_MAILBOX_TO_DSP};

/// Servo period: 2500 clocks, 50 µs (20 kHz) at 50 MHz.
pub const TICK_CLOCKS: u32 = 2500;
/// PID: Kp in DAC codes per count, τi and τd in seconds, tuned on the
/// plant of `plant.rs` with the 1 mm move of tests/servo_loop.rs (Kp 40 or
/// 80, τd 4 or 8 ms, τi 20 ms, 100 ms or off: this one overshot least,
/// 4 counts, and settled to ±2 counts within 34 ms).
pub const KP: f64 = 80.0;
pub const TAU_I_S: f64 = 0.1;
pub const TAU_D_S: f64 = 0.008;

/// The gains the firmware runs with.
pub fn gains() -> PidGains {
    PidGains::from_times(KP, f64::from(TICK_CLOCKS) * CLOCK_S, TAU_I_S, TAU_D_S)
}

/// One servo period as the firmware and the bench saw it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tick {
    /// The card's clock at the tick's interrupt.
    pub clock: u64,
    /// The fine setpoint, counts.
    pub setpoint: [f64; AXES],
    /// COUNT as read (the tick's snapshot).
    pub count: [i32; AXES],
    /// The codes staged for the next tick (straight binary).
    pub code: [u16; AXES],
    /// The codes the DAC outputs now.
    pub dac: [u16; AXES],
    /// The slides' positions (counts, not rounded) and speeds (m/s) now.
    pub position: [f64; AXES],
    pub velocity: [f64; AXES],
}

/// The coarse points as the PC sends them: per point and axis a 32-bit
/// count, low half first.
pub fn encode_points(points: &[[i32; AXES]]) -> Vec<u16> {
    points
        .iter()
        .flat_map(|p| p.iter().flat_map(|&c| [c as u16, (c as u32 >> 16) as u16]))
        .collect()
}

/// After reset: the e-stop latch released, counters ×4, the interrupt on
/// the servo tick and the doorbell.
pub fn setup(card: &mut ServoCard) {
    card.reset();
    card.write("SAFETY", None, "CLEAR", 1);
    for i in 0..AXES as u32 {
        card.write("COUNTER", Some(i), "CTRL", mode::X4);
    }
    let cause = card.map().block("SAFETY").register("CAUSE").clone();
    let mask = cause.field("SERVO_TICK").mask() | cause.field("DOORBELL").mask();
    card.write("SAFETY", None, "CAUSE_MASK", mask);
}

/// Waits for the PC's doorbell and reads the points it sent (the mailbox
/// word holds the number of RAM words).
pub fn receive_points(card: &mut ServoCard) -> Vec<[i32; AXES]> {
    assert!(card.wait_irq(1_000_000), "no doorbell from the PC");
    let cause = card.map().block("SAFETY").register("CAUSE").clone();
    let bell = cause.field("DOORBELL").mask();
    assert_ne!(
        card.read("SAFETY", None, "CAUSE") & bell,
        0,
        "IRQ without DOORBELL"
    );
    card.write("SAFETY", None, "CAUSE", bell);
    let words = card.read_ram(ISA_MAILBOX_TO_DSP as u16);
    let data: Vec<u16> = (0..words).map(|w| card.read_ram(w)).collect();
    data.chunks(2 * AXES)
        .map(|p| {
            std::array::from_fn(|i| (u32::from(p[2 * i]) | u32::from(p[2 * i + 1]) << 16) as i32)
        })
        .collect()
}

/// The fine setpoints: the coarse points clamped (the curve starts and
/// ends on them), `n` fine points per span.
pub fn fine_setpoints(coarse: &[[i32; AXES]], n: u32) -> Vec<[f64; AXES]> {
    let c: Vec<[f64; AXES]> = coarse.iter().map(|p| p.map(f64::from)).collect();
    FineInterpolator::new(&clamped(&c), n).collect()
}

/// Starts the servo tick and runs `ticks` periods: per tick the interrupt,
/// the snapshot counts, a PID step per axis toward the next setpoint (the
/// last one held), the codes staged, the cause cleared. `bench` runs at
/// every tick before the firmware (an e-stop, a disturbance).
pub fn run(
    card: &mut ServoCard,
    setpoints: &[[f64; AXES]],
    ticks: usize,
    bench: impl FnMut(usize, &mut ServoCard),
) -> Vec<Tick> {
    run_with(card, gains(), setpoints, ticks, bench)
}

/// [`run`] with other gains.
pub fn run_with(
    card: &mut ServoCard,
    gains: PidGains,
    setpoints: &[[f64; AXES]],
    ticks: usize,
    mut bench: impl FnMut(usize, &mut ServoCard),
) -> Vec<Tick> {
    let mut pid = [IncrementalPid::new(gains); AXES];
    let tick_bit = card
        .map()
        .block("SAFETY")
        .register("CAUSE")
        .field("SERVO_TICK")
        .mask();
    card.write("SERVO", None, "TICK_PERIOD", TICK_CLOCKS);
    let mut log = Vec::with_capacity(ticks);
    for k in 0..ticks {
        assert!(
            card.wait_irq(2 * u64::from(TICK_CLOCKS)),
            "no servo tick at period {k}"
        );
        bench(k, card);
        let clock = card.clocks;
        let count: [i32; AXES] =
            std::array::from_fn(|i| card.read("COUNTER", Some(i as u32), "COUNT") as i32);
        let setpoint = setpoints[k.min(setpoints.len() - 1)];
        let mut code = [0u16; AXES];
        for i in 0..AXES {
            let e = setpoint[i].round() as i32 - count[i];
            code[i] = dac_offset_binary(pid[i].update(e));
            card.write("SERVO", Some(i as u32), "CODE", u32::from(code[i]));
        }
        card.write("SAFETY", None, "CAUSE", tick_bit);
        log.push(Tick {
            clock,
            setpoint,
            count,
            code,
            dac: [card.dac_output()[0], card.dac_output()[1]],
            position: card.axes.map(|a| a.counts()),
            velocity: card.axes.map(|a| a.velocity),
        });
    }
    log
}
