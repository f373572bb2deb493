//! Counter bank: exhaustive checks, wrap-around, random motion against the
//! model and against the true displacement, and the generated Verilog.

use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap;
use motionhdl_testbench::checks::counter_bank::{self, BankPair};
use motionhdl_testbench::checks::counter_channel::{self, ctrl_value};
use motionhdl_testbench::checks::input_filter;
use motionhdl_testbench::harness::require_tool;
use motionhdl_testbench::scale;
use motionhdl_testbench::scenarios::counter_bank::quadrature;
use motionhdl_testbench::verilog_sim::Simulator;
use proptest::prelude::*;

#[test]
fn input_filter_every_reachable_state_and_input_for_every_setting() {
    let r = input_filter::filter_exhaustive();
    assert!(r.expected > 16 * 4, "enumerated only {} pairs", r.expected);
    r.assert_passed();
}

#[test]
fn channel_core_every_reachable_state_and_input_in_each_mode() {
    let reports = counter_channel::core_checks();
    assert_eq!(
        reports.len(),
        7,
        "five modes, X4 reversed, every index feature"
    );
    for r in reports {
        assert!(
            r.expected > 1000,
            "{}: enumerated only {} pairs",
            r.check,
            r.expected
        );
        r.assert_passed();
    }
}

/// The largest `width`-bit count: -1 read sign-extended.
fn top_count(width: u32) -> u32 {
    u32::MAX >> (32 - width)
}

/// Preset near the top of the range, count through the wrap in both
/// directions, read sign-extended COUNT over the bus.
fn wrap_around<const N: usize>(width: u32) {
    let mut p = BankPair::<N>::new(width, regmap::ERR_COUNT_BITS);
    let map = regmap::counter_bank(N as u32, width);
    let ch = map.array("CH");
    let idle = [(false, false, false); N];
    let top = top_count(width);
    p.reset(&idle, 3).unwrap();
    p.write(
        &idle,
        ch.address(0, "CTRL"),
        ctrl_value(width, &[("MODE", regmap::mode::X4)]),
    )
    .unwrap();
    p.write(&idle, map.register("PRESET").offset, top - 1)
        .unwrap(); // -2
    let load = ch.register("CMD").field("LOAD").mask();
    p.write(&idle, ch.address(0, "CMD"), load).unwrap();
    p.step(&idle, false, &BusCycle::default()).unwrap(); // LOAD's second edge
    let snapshot = map.register("SNAPSHOT").offset;
    let read_count = |p: &mut BankPair<N>| -> i32 {
        p.write(&idle, snapshot, 0).unwrap();
        p.read(&idle, ch.address(0, "COUNT")).unwrap() as i32
    };
    assert_eq!(read_count(&mut p), -2, "W={width}");
    let mut pins = idle;
    let mut phase = 0u8;
    let mut go = |p: &mut BankPair<N>, steps: i32| {
        for _ in 0..steps.unsigned_abs() {
            phase = if steps > 0 { phase + 1 } else { phase + 3 } & 3;
            let (a, b) = quadrature(phase);
            pins[0] = (a, b, false);
            p.step(&pins, false, &BusCycle::default()).unwrap();
        }
        for _ in 0..4 {
            p.step(&pins, false, &BusCycle::default()).unwrap();
        }
    };
    go(&mut p, 4); // -2 + 4 = 2 through the top
    assert_eq!(p.model.channel(0).state().count, 2, "W={width}");
    go(&mut p, -5); // 2 - 5 = -3 through zero
    assert_eq!(p.model.channel(0).state().count, top - 2, "W={width}");
    let pins_now = pins;
    p.write(&pins_now, snapshot, 0).unwrap();
    assert_eq!(
        p.read(&pins_now, ch.address(0, "COUNT")).unwrap() as i32,
        -3,
        "W={width}"
    );
}

#[test]
fn full_width_wrap_around_at_28_and_32_bits() {
    wrap_around::<1>(28);
    wrap_around::<1>(32);
    wrap_around::<4>(28);
}

/// Presets whose low half (the split counter's look-ahead) is all ones, all
/// zeros or neither, loaded and then stepped once each way: the bank's
/// load-time flags must match the count (`BankPair` checks every clock),
/// and the first step must carry or borrow across the halves. Random
/// presets hit these low halves once in 2^13.
#[test]
fn a_preset_on_a_half_boundary_counts_on_from_it() {
    let mut cases = 0;
    for width in [28, 32] {
        let map = regmap::counter_bank(1, width);
        let ch = map.array("CH");
        let (load, preset) = (
            ch.register("CMD").field("LOAD").mask(),
            map.register("PRESET").offset,
        );
        let top = top_count(width);
        let low = (1u32 << (width / 2)) - 1;
        let idle = [(false, false, false)];
        let ctrl = ctrl_value(width, &[("MODE", regmap::mode::X4)]);
        for value in [low, low - 1, 0, low + 1, top, top - low, top & !low | 1] {
            for forward in [true, false] {
                let mut p = BankPair::<1>::new(width, regmap::ERR_COUNT_BITS);
                let bus = [
                    (ch.address(0, "CTRL"), ctrl),
                    (preset, value),
                    (ch.address(0, "CMD"), load),
                ];
                let at = format!("W={width} preset {value:#x} forward {forward}");
                p.reset(&idle, 3).unwrap();
                for (addr, data) in bus {
                    p.write(&idle, addr, data)
                        .unwrap_or_else(|e| panic!("{at}: {e}"));
                }
                let (a, b) = quadrature(if forward { 1 } else { 3 });
                for _ in 0..6 {
                    p.step(&[(a, b, false)], false, &BusCycle::default())
                        .unwrap_or_else(|e| panic!("{at}: {e}"));
                }
                let step = if forward { 1 } else { top };
                let want = value.wrapping_add(step) & top;
                assert_eq!(p.model.channel(0).state().count, want, "{at}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 28);
}

/// One move in a random encoder motion.
#[derive(Clone, Debug)]
enum Move {
    Step {
        forward: bool,
        hold: usize,
    },
    Idle(usize),
    /// A and B flip together: an illegal jump of two Gray steps.
    Jump,
    /// A pulse on A shorter than the filter, which must be rejected.
    Bounce(usize),
    Index(usize),
}

fn motion() -> impl Strategy<Value = Vec<Move>> {
    let m = prop_oneof![
        6 => (any::<bool>(), 0usize..6).prop_map(|(forward, hold)| Move::Step { forward, hold }),
        2 => (1usize..10).prop_map(Move::Idle),
        1 => Just(Move::Jump),
        2 => (1usize..4).prop_map(Move::Bounce),
        1 => (1usize..4).prop_map(Move::Index),
    ];
    prop::collection::vec(m, 1..150)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random encoder motion on two channels (X4 with a filter, X2 without),
    /// HDL vs model every clock; with no illegal jump, the X4 count equals
    /// the true net displacement of the motion.
    #[test]
    fn random_motion_hdl_matches_model_and_true_displacement(moves in motion(), filter in 0u32..4) {
        let width = 28;
        let mut p = BankPair::<2>::new(width, regmap::ERR_COUNT_BITS);
        let map = regmap::counter_bank(2, width);
        let ch = map.array("CH");
        let mut pins = [(false, false, false); 2];
        p.reset(&pins, 3).unwrap();
        let ctrl0 = ctrl_value(width, &[("MODE", regmap::mode::X4), ("FILTER_AB", filter), ("ERR_EN", 1), ("IDX_LATCH", 1)]);
        let ctrl1 = ctrl_value(width, &[("MODE", regmap::mode::X2), ("ERR_EN", 1)]);
        p.write(&pins, ch.address(0, "CTRL"), ctrl0).unwrap();
        p.write(&pins, ch.address(1, "CTRL"), ctrl1).unwrap();
        let settle = filter as usize + 4;
        let mut phase = 0u8;
        let mut displacement: i64 = 0;
        let mut jumped = false;
        let clock = |p: &mut BankPair<2>, pins: &[(bool, bool, bool); 2], n: usize| -> Result<(), TestCaseError> {
            for _ in 0..n {
                p.step(pins, false, &BusCycle::default()).map_err(TestCaseError::fail)?;
            }
            Ok(())
        };
        for m in &moves {
            match *m {
                Move::Step { forward, hold } => {
                    phase = if forward { phase + 1 } else { phase + 3 } & 3;
                    displacement += if forward { 1 } else { -1 };
                    let (a, b) = quadrature(phase);
                    pins = [(a, b, false); 2];
                    clock(&mut p, &pins, settle + hold)?;
                }
                Move::Idle(n) => clock(&mut p, &pins, n)?,
                Move::Jump => {
                    jumped = true;
                    phase = (phase + 2) & 3;
                    let (a, b) = quadrature(phase);
                    pins = [(a, b, false); 2];
                    clock(&mut p, &pins, settle)?;
                }
                Move::Bounce(len) if filter > 0 => {
                    // Shorter than the filter on channel 0 only.
                    let len = len.min(filter as usize);
                    let saved = pins[0];
                    pins[0].0 = !pins[0].0;
                    clock(&mut p, &pins, len)?;
                    pins[0] = saved;
                    clock(&mut p, &pins, settle)?;
                }
                Move::Bounce(_) => clock(&mut p, &pins, 1)?,
                Move::Index(len) => {
                    pins[0].2 = true;
                    clock(&mut p, &pins, len)?;
                    pins[0].2 = false;
                    clock(&mut p, &pins, 1)?;
                }
            }
        }
        clock(&mut p, &pins, settle)?;
        if !jumped {
            let top = (1i64 << width) - 1;
            prop_assert_eq!(i64::from(p.model.channel(0).state().count), displacement & top);
            prop_assert!(!p.model.channel(0).state().err);
        }
    }
}

/// The same long stimulus through the model and the rust-hdl bank (every
/// register compared every clock), and both stimulus generators agree.
#[test]
fn long_stimulus_rust_hdl_matches_model() {
    let r = counter_bank::long_stimulus_hdl(20_000);
    assert_eq!(r.expected, 20_000);
    r.assert_passed();
}

#[test]
fn generated_verilog_in_icarus_matches_model() {
    if require_tool("iverilog").is_none() {
        return;
    }
    counter_bank::verilog_long_run(Simulator::Icarus, 30_000).assert_passed();
}

#[test]
fn generated_verilog_in_verilator_matches_model_for_the_long_run() {
    if require_tool("verilator").is_none() {
        return;
    }
    // 10^6 clocks at the default scale, 10^7 at the long one.
    let clocks = scale::cases("counter_bank_verilator_clocks");
    let r = counter_bank::verilog_long_run(Simulator::Verilator, clocks);
    assert_eq!(r.expected, clocks);
    r.assert_passed();
}
