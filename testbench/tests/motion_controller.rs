//! The top level through the MCU's pins: every register word of the map read
//! after reset, reserved and read-only words written (nothing changes),
//! every channel configured, the whole RAM window written and read back,
//! by the STM32F4 FSMC bus-functional model with the documented timing, in
//! rust-hdl and in the generated Verilog (Icarus, Verilator), against the
//! table, the counter bank model and a RAM array.

use motionhdl_hdl::catalog;
use motionhdl_model::regmap;
use motionhdl_model::servo_dac::SAFE_CODE;
use motionhdl_model::{Config, IsaRam};
use motionhdl_testbench::bfm::fsmc::{Observation, Op};
use motionhdl_testbench::checks::motion_controller::{self as top, McuOracle, Plan};
use motionhdl_testbench::verilog_sim::Simulator;
use motionhdl_testbench::CheckReport;
use motionhdl_testbench::{harness, scale};
use std::sync::OnceLock;

fn config() -> Config {
    Config::default()
}

fn external() -> Config {
    Config::default().with_isa_ram(IsaRam::External)
}

/// The external-RAM build at the scale's axis count (knob
/// `external_ram_walk_axes`: 1 at the default scale, the default's 4 at
/// the long one). The walk's reads are the same at every axis count (the
/// map's 1024 words); an axis is one block's logic repeated, which the
/// default build's walks above check at 4.
fn external_walked() -> Config {
    external()
        .with_axes(scale::cases("external_ram_walk_axes"))
        .expect("external_ram_walk_axes is 1..=16")
}

/// The rust-hdl top of `config`'s axis count (one of 1, 2, 4: the const
/// generic the tops take).
fn run_rust_at(config: &Config, ops: &[Op]) -> Vec<Observation> {
    match config.axes() {
        1 => top::run_rust::<1>(config, ops).0,
        2 => top::run_rust::<2>(config, ops).0,
        4 => top::run_rust::<4>(config, ops).0,
        n => panic!("no rust-hdl top of {n} axes here: use 1, 2 or 4"),
    }
}

/// PRESET, SNAPSHOT and CTRL/CMD of `axes` channels; RUN and 13 registers
/// of each pulse axis (CTRL, RATE, two timings, five SEG_*,
/// FIFO_LOW_WATER, SOFT_MIN, SOFT_MAX, DECEL); 31 SAFETY registers.
fn writable_words(axes: u64) -> u64 {
    2 + axes * 2 + 1 + axes * 13 + 31
}

/// The register words of `config`'s map that the oracle takes writes to.
fn writable_count(config: &Config) -> u64 {
    let o = McuOracle::new(config);
    (0..top::REGISTER_WORDS).filter(|w| o.writable(*w)).count() as u64
}

fn plan() -> &'static Plan {
    static PLAN: OnceLock<Plan> = OnceLock::new();
    PLAN.get_or_init(|| top::plan(&config()))
}

fn external_plan() -> &'static Plan {
    static PLAN: OnceLock<Plan> = OnceLock::new();
    PLAN.get_or_init(|| top::plan(&external_walked()))
}

/// Halfword reads the plan makes: three passes over every register word
/// (two halves each), every RAM word as 16-bit, 32 RAM pairs as 32-bit.
const EXPECTED_READS: u64 = 3 * 1024 * 2 + 1024 + 32 * 2;
/// Without a RAM window: the register passes, 4 halfword probes of the
/// window and one 32-bit probe.
const EXPECTED_READS_EXTERNAL: u64 = 3 * 1024 * 2 + 4 + 2;

#[test]
fn the_plan_covers_the_map() {
    let p = plan();
    assert_eq!(p.expected.len() as u64, EXPECTED_READS);
    let o = McuOracle::new(&config());
    // Every register word is either writable or among the ignored writes.
    let writable = writable_count(&config());
    assert_eq!(writable + p.ignored_writes, u64::from(top::REGISTER_WORDS));
    // The 31 SAFETY registers are all but INFO, STATUS, WDT_COUNT, the
    // two machine-input level registers and GPI_LEVEL.
    assert_eq!(writable, writable_words(4));
    // The ID block reads its table values after reset.
    let id = o.map().block("ID");
    assert_eq!(o.read32(id.base), regmap::ID_MAGIC);
    let reads = &p.expected[..2 * top::REGISTER_WORDS as usize];
    let word =
        |w: u32| u32::from(reads[2 * w as usize]) | u32::from(reads[2 * w as usize + 1]) << 16;
    for r in &id.registers {
        assert_eq!(word(id.base + r.offset), r.reset, "ID.{}", r.name);
    }
    // After reset the e-stop latch is set and, the chain closed, the
    // input reads released: STATUS = ESTOP only.
    let safety = o.map().block("SAFETY");
    let status = safety.register("STATUS");
    assert_eq!(
        word(safety.base + status.offset),
        status.field("ESTOP").mask()
    );
    let counter = o.map().block("COUNTER");
    assert_eq!(
        word(counter.base + counter.register("INFO").offset),
        counter.register("INFO").reset
    );
    // The oracle sees writes to reserved words as nothing.
    assert!((0..top::REGISTER_WORDS).any(|w| o.decode(w).is_none()));
}

fn check(
    name: &str,
    plan: &Plan,
    got: Result<Vec<Observation>, String>,
    sim: Option<Simulator>,
) -> CheckReport {
    match got {
        Ok(obs) => top::compare(name, plan, &obs),
        Err(e) => {
            let mut r = CheckReport::new("motion_controller", name, plan.expected.len() as u64);
            if sim.is_some_and(|s| s.available().is_err()) {
                return r.skip(e);
            }
            r.failures.push(e);
            r
        }
    }
}

#[test]
fn every_register_and_ram_word_through_fsmc_rust_hdl() {
    let (obs, clocks) = top::run_rust::<4>(&config(), &plan().ops);
    let r = check(
        "every register and RAM word, rust-hdl",
        plan(),
        Ok(obs),
        None,
    );
    assert!(clocks > 50_000, "{clocks} clocks");
    assert_eq!(r.expected, EXPECTED_READS);
    r.assert_passed();
    assert_eq!(r.covered, EXPECTED_READS);
}

#[test]
fn external_top_window_pins_reach_a_board_ram() {
    // 1024 halfword reads and 32 32-bit pairs: every window word written
    // and read back through the window_* pins.
    let reads = (top::WINDOW_WORDS + 64) as u64;
    let mut ram = top::WindowRam::new(|a| a);
    let r = top::external_window_rust(&external(), &mut ram);
    r.assert_passed();
    assert_eq!(r.covered, reads);
    assert_eq!(ram.writes, reads, "one RAM write per halfword written");
    assert_eq!(ram.sram_driven, 0, "the idle PC side drove the SRAM");
    // A board whose A9 is stuck low: the upper half's writes land on the
    // lower half, whose 512 reads then return the wrong words, from the
    // first one on (the report keeps 20 and says there were more).
    let mut stuck = top::WindowRam::new(|a| a & 0x1ff);
    let r = top::external_window_rust(&external(), &mut stuck);
    assert_eq!(r.covered, reads);
    assert_eq!(r.failures.len(), 21, "{:?}", r.failures);
    assert!(
        r.failures[0].starts_with("read #0 (Read16 A=0x800)"),
        "{}",
        r.failures[0]
    );
}

#[test]
fn every_register_and_ram_word_through_fsmc_icarus() {
    let sim = Simulator::Icarus;
    let r = check(
        "every register and RAM word, Icarus",
        plan(),
        top::run_verilog(sim, &config(), &plan().ops),
        Some(sim),
    );
    r.assert_passed();
    if r.skipped.is_none() {
        assert_eq!(r.covered, EXPECTED_READS);
    }
}

#[test]
fn every_register_and_ram_word_through_fsmc_verilator() {
    let sim = Simulator::Verilator;
    let r = check(
        "every register and RAM word, Verilator",
        plan(),
        top::run_verilog(sim, &config(), &plan().ops),
        Some(sim),
    );
    r.assert_passed();
    if r.skipped.is_none() {
        assert_eq!(r.covered, EXPECTED_READS);
    }
}

#[test]
fn a_wrong_register_value_is_caught() {
    // The comparison must fail when the oracle is wrong: flip one bit of
    // ID.MAGIC's expected low half.
    let mut wrong = top::plan(&config());
    wrong.expected[0] ^= 1;
    let (obs, _) = top::run_rust::<4>(&config(), &plan().ops[..1 + 4]);
    let mut truncated = Plan {
        ops: plan().ops[..5].to_vec(),
        expected: wrong.expected[..8].to_vec(),
        ignored_writes: 0,
    };
    let r = top::compare("mutated oracle", &truncated, &obs);
    assert_eq!(r.failures.len(), 1, "{:?}", r.failures);
    truncated.expected[0] ^= 1;
    assert!(top::compare("oracle", &truncated, &obs).failures.is_empty());
}

#[test]
fn external_ram_build_registers_and_no_ram_window() {
    let p = external_plan();
    assert_eq!(p.expected.len() as u64, EXPECTED_READS_EXTERNAL);
    let config = external_walked();
    assert_eq!(
        writable_count(&config),
        writable_words(config.axes().into())
    );
    let obs = run_rust_at(&config, &p.ops);
    let r = check("external RAM build, rust-hdl", p, Ok(obs), None);
    r.assert_passed();
    assert_eq!(r.covered, EXPECTED_READS_EXTERNAL);
    for sim in [Simulator::Icarus, Simulator::Verilator] {
        let r = check(
            &format!("external RAM build, {}", sim.name()),
            p,
            top::run_verilog(sim, &config, &p.ops),
            Some(sim),
        );
        r.assert_passed();
        if r.skipped.is_none() {
            assert_eq!(r.covered, EXPECTED_READS_EXTERNAL);
        }
    }
}

/// The servo card at the scale's axis count (knob `servo_card_walk_axes`:
/// 1 at the default scale, the card's 2 at the long one).
fn servo() -> Config {
    Config::default()
        .with_axes(scale::cases("servo_card_walk_axes"))
        .expect("servo_card_walk_axes is 1..=16")
        .with_servo_dac(true)
}

#[test]
fn servo_card_build_registers_through_fsmc() {
    // The servo card's top: the plan covers SERVO too (TIMING, SERIAL,
    // PREFIX, the codes, UPDATE, TICK_PERIOD, EVENTS), read back through
    // the same decode.
    let config = servo();
    let p = top::plan(&config);
    assert_eq!(p.expected.len() as u64, EXPECTED_READS);
    let o = McuOracle::new(&config);
    let writable = writable_count(&config);
    // The channels, axes and SAFETY as above; SERVO: EVENTS, TICK_PERIOD,
    // UPDATE, TIMING, SERIAL, PREFIX and the 4 CODE registers.
    assert_eq!(writable, writable_words(config.axes().into()) + 10);
    let servo = o.map().block("SERVO");
    assert_eq!(servo.base, regmap::MCU_SERVO_WORD_BASE);
    // The e-stop latch is set from reset (HALT), so the plan's UPDATE sent
    // the safe code: OUTPUT reads SAFE_CODE, CODE the staged value.
    let last = &p.expected[4 * top::REGISTER_WORDS as usize..6 * top::REGISTER_WORDS as usize];
    let word = |w: u32| u32::from(last[2 * w as usize]) | u32::from(last[2 * w as usize + 1]) << 16;
    let ch = servo.array("CH");
    for i in 0..ch.count {
        let code = word(servo.base + ch.address(i, "CODE"));
        assert_eq!(
            word(servo.base + ch.address(i, "OUTPUT")),
            SAFE_CODE,
            "CH[{i}]"
        );
        assert_ne!(
            code, SAFE_CODE,
            "CH[{i}]: the plan's code is not the reset value"
        );
    }
    let safe = servo.register("STATUS").field("SAFE").mask();
    assert_eq!(
        word(servo.base + servo.register("STATUS").offset) & safe,
        safe
    );
    let obs = run_rust_at(&config, &p.ops);
    let r = check("servo card build, rust-hdl", &p, Ok(obs), None);
    r.assert_passed();
    assert_eq!(r.covered, EXPECTED_READS);
    for sim in [Simulator::Icarus, Simulator::Verilator] {
        let r = check(
            &format!("servo card build, {}", sim.name()),
            &p,
            top::run_verilog(sim, &config, &p.ops),
            Some(sim),
        );
        r.assert_passed();
        if r.skipped.is_none() {
            assert_eq!(r.covered, EXPECTED_READS);
        }
    }
}

#[test]
fn both_builds_export_module_motion_controller() {
    let internal = catalog::motion_controller(&config()).text;
    let outside = catalog::motion_controller(&external()).text;
    for text in [&internal, &outside] {
        assert!(text.contains("module motion_controller("));
    }
    assert!(!internal.contains("sram_we_n"));
    assert!(outside.contains("sram_we_n"));
}

#[test]
fn loopback_through_the_pins_in_the_generated_verilog() {
    // Pulse outputs wired to the encoder inputs of the same top; every
    // axis counts exactly the steps it emitted, in every output mode, and
    // the Verilog agrees with rust-hdl value for value.
    let rust = top::loopback_rust(&config()).unwrap();
    for (i, (count, position)) in rust.iter().enumerate() {
        assert_eq!(count, position, "rust-hdl: axis {i}");
        assert!(
            position.abs() > 20,
            "rust-hdl: axis {i} moved only {position}"
        );
    }
    for sim in [Simulator::Icarus, Simulator::Verilator] {
        match top::loopback_verilog(sim, &config()) {
            Ok(axes) => {
                assert_eq!(axes.len(), 4);
                assert_eq!(axes, rust, "{} against rust-hdl", sim.name());
                for (i, (count, position)) in axes.iter().enumerate() {
                    assert_eq!(count, position, "{}: axis {i}", sim.name());
                    assert!(
                        position.abs() > 20,
                        "{}: axis {i} moved only {position}",
                        sim.name()
                    );
                }
            }
            Err(e) if sim.available().is_err() => harness::skip_test(&e),
            Err(e) => panic!("{}: {e}", sim.name()),
        }
    }
}

#[test]
fn a_segment_move_through_the_top_ends_on_target_and_is_counted() {
    use motionhdl_model::regmap;
    let map = regmap::mcu_map(&config());
    let status = map.block("PULSE").array("AX").register("STATUS");
    let target: i32 = top::MOVE_SEGMENTS
        .iter()
        .map(|&(steps, rate, _)| steps as i32 * rate.signum())
        .sum();
    assert_eq!(target, 95);
    let check = |who: &str, (s, count, position): (u32, i32, i32)| {
        assert_eq!(status.field("DONE").get(s), 1, "{who}: STATUS {s:#x}");
        assert_eq!(status.field("BUSY").get(s), 0, "{who}: STATUS {s:#x}");
        assert_eq!(status.field("OVERFLOW").get(s), 0, "{who}: STATUS {s:#x}");
        assert_eq!(position, target, "{who}: POSITION");
        assert_eq!(count, target, "{who}: COUNT");
    };
    let rust = top::moves_rust(&config()).unwrap();
    check("rust-hdl", rust);
    // Icarus once spun for ever at one simulation time here: two
    // `always @(*)` blocks re-set each other's inputs through default-then-
    // override assignments (see PulseGenerator::update).
    for sim in [Simulator::Icarus, Simulator::Verilator] {
        match top::moves_verilog(sim, &config()) {
            Ok(got) => {
                check(sim.name(), got);
                assert_eq!(got, rust, "{} against rust-hdl", sim.name());
            }
            Err(e) if sim.available().is_err() => harness::skip_test(&e),
            Err(e) => panic!("{}: {e}", sim.name()),
        }
    }
}
