//! The firmware driver ([`motionhdl_driver`], the code C firmware links)
//! against the whole controller in simulation: every call is FSMC bus
//! operations into the rust-hdl top of the default configuration (the
//! map the driver is built for). The card check, a two-axis move streamed
//! through the FIFOs with refills and started in one write, coherent
//! reads, the watchdog's bite, the e-stop, the shared RAM. A wrong offset
//! in the driver's register module fails these (the homing tests run the
//! driver too).

use motionhdl_driver::{AxisSample, Card, Error, Segment, Stream, FIFO_DEPTH};
use motionhdl_model::regmap::mode;
use motionhdl_model::Config;
use motionhdl_testbench::bfm::fsmc::Op;
use motionhdl_testbench::checks::motion_controller::driver_bus::SETUP_AXIS;
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};

const ESTOP: u32 = 1 << 1;
const BITTEN: u32 = 1 << 2;
const WATCHDOG_CAUSE: u32 = 1 << 1;

/// The default controller out of reset, set up through the driver: the
/// halt released, counters ×4, pulse+direction with 2-clock steps.
fn card() -> Card<System<4>> {
    let mut sys = System::<4>::on(Engine::for_scenarios(), &Config::default());
    sys.exec(Op::Reset);
    let mut card = Card::new(sys);
    assert_eq!(card.check().map(|v| v >> 8), Ok(1), "ID.VERSION 0.1.x");
    card.clear_halt().expect("the e-stop input is released");
    for axis in 0..4 {
        card.counter_configure(axis, mode::X4).unwrap();
        card.axis_configure(axis, &SETUP_AXIS).unwrap();
    }
    card
}

#[test]
fn the_check_refuses_a_card_with_another_map() {
    let mut two = System::<2>::on(
        Engine::for_scenarios(),
        &Config::new(2, 28, 50_000_000).unwrap(),
    );
    two.exec(Op::Reset);
    let got = Card::new(&mut two).check();
    assert!(
        matches!(got, Err(Error::MapHash(h)) if h != motionhdl_driver::regs::MAP_HASH),
        "{got:?}"
    );
}

/// `n` constant-rate segments of `steps` steps, a step every `period` clocks.
fn constant(n: usize, steps: u32, period: i64, sign: i64) -> Vec<Segment> {
    let rate = ((1i64 << 32) / period * sign) as i32;
    vec![
        Segment {
            steps,
            rate,
            accel: 0,
            jerk: 0
        };
        n
    ]
}

#[test]
fn a_streamed_two_axis_move_ends_where_planned() {
    let mut card = card();
    // More segments than the FIFO holds: the rest go in as it drains.
    let x = constant(FIFO_DEPTH as usize + 36, 3, 12, 1);
    let y = constant(50, 2, 16, -1);
    let (mut sx, mut sy) = (Stream::new(0), Stream::new(1));
    assert_eq!(
        sx.refill(&mut card, &x),
        Ok(false),
        "the FIFO is full first"
    );
    assert_eq!(sy.refill(&mut card, &y), Ok(true));
    card.enable_drives(0b11).unwrap();
    card.start(0b11).unwrap();
    let start = card.bus().clocks;
    let mut refills = 0;
    loop {
        let pushed = sx.refill(&mut card, &x).unwrap() & sy.refill(&mut card, &y).unwrap();
        refills += 1;
        if pushed && card.move_done(0).unwrap() && card.move_done(1).unwrap() {
            break;
        }
        assert!(
            card.bus().clocks - start < 200_000,
            "the move did not finish"
        );
    }
    assert!(refills > 1, "refilled while running");
    card.bus().idle(20); // the last steps reach the shafts and the encoders
    let mut s = [AxisSample::default(); 4];
    card.sample(&mut s).unwrap();
    assert_eq!((s[0].position, s[1].position), (300, -100), "{s:?}");
    assert_eq!(
        (s[0].count, s[1].count),
        (300, -100),
        "the encoders count what went out"
    );
    assert_eq!((s[2].position, s[3].count), (0, 0));
    let shafts: Vec<i32> = card.bus().drives.iter().map(|d| d.position).collect();
    assert_eq!(shafts, [300, -100, 0, 0]);
    let causes = card.causes();
    assert_eq!(causes.done & 0b11, 0b11, "{causes:?}");
    card.clear_causes(&causes);
    assert_eq!(card.causes().done, 0);
}

#[test]
fn the_watchdog_bites_unfed_and_the_driver_recovers() {
    let mut card = card();
    card.enable_drives(0b1).unwrap();
    card.watchdog_arm(2_000);
    for _ in 0..5 {
        card.bus().idle(1_000);
        card.watchdog_feed();
    }
    assert_eq!(card.safety_status() & BITTEN, 0, "fed in time");
    assert_eq!(card.bus().drive_enable(), 1);
    card.bus().idle(2_500);
    assert_ne!(card.safety_status() & BITTEN, 0, "bitten");
    assert_eq!(card.bus().drive_enable(), 0, "drives off");
    assert_eq!(card.causes().card & WATCHDOG_CAUSE, WATCHDOG_CAUSE);
    card.watchdog_arm(0);
    card.clear_halt().unwrap();
    card.enable_drives(0b1).unwrap();
    assert_eq!(card.bus().drive_enable(), 1, "enabled again");
}

#[test]
fn the_estop_holds_until_its_input_is_released() {
    let mut card = card();
    card.enable_drives(0b1111).unwrap();
    card.bus().estop_ok = false;
    card.bus().idle(10);
    assert_ne!(card.safety_status() & ESTOP, 0);
    assert_eq!(card.bus().drive_enable(), 0);
    assert_eq!(card.clear_halt(), Err(Error::EstopInput));
    card.bus().estop_ok = true;
    card.bus().idle(10);
    assert_eq!(card.clear_halt(), Ok(()));
    assert_eq!(
        card.bus().drive_enable(),
        0,
        "drives stay off until enabled"
    );
}

#[test]
fn shared_ram_blocks_round_trip() {
    let mut card = card();
    let data: Vec<u16> = (0..16).map(|i| 0x1111 * (i % 15 + 1)).collect();
    card.ram_write(1000, &data).unwrap();
    let mut back = [0u16; 16];
    card.ram_read(1000, &mut back).unwrap();
    assert_eq!(back.to_vec(), data);
    assert_eq!(card.ram_write(1020, &data), Err(Error::Argument));
}
