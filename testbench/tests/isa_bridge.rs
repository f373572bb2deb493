//! ISA bridge, both RAM builds: exhaustive cases, block transfers, random
//! bus traffic and the same-clock write rule, in rust-hdl and the generated
//! Verilog (Icarus, Verilator).

use motionhdl_model::IsaRam;
use motionhdl_testbench::bfm::isa::{Observation, Op};
use motionhdl_testbench::checks::isa_bridge as isa;
use motionhdl_testbench::verilog_sim::Simulator;

const BUILDS: [IsaRam; 2] = [IsaRam::Internal, IsaRam::External];

#[test]
fn exhaustive_cases_rust_hdl() {
    for ram in BUILDS {
        let r = isa::exhaustive_rust(ram);
        assert_eq!(r.expected, 6400);
        r.assert_passed();
    }
}

#[test]
fn block_transfers_rust_hdl() {
    for ram in BUILDS {
        let r = isa::block_transfer_rust(ram);
        assert_eq!(r.expected, 6144);
        r.assert_passed();
    }
}

#[test]
fn the_external_top_carries_the_bridge_rust_hdl() {
    // The top's isa_* and sram_* pins, the FSMC idle, behave as the
    // bridge's own: every output before every edge (the bell to the DSP
    // read at the MCU side's doorbell input), the SRAM pins and the
    // address counter after it, every read.
    let (r, run) = isa::external_top_rust(isa::LONG_RANDOM.0, 1000);
    r.assert_passed();
    assert_eq!(r.covered, r.expected);
    assert!(r.expected > 1000, "{}", r.expected);
    // The PC rang the DSP; the FPGA cannot see the DSP's port, so its
    // IRQ stays low (docs/isa_bridge.md).
    assert!(run.bells_to_dsp >= 2, "bells {}", run.bells_to_dsp);
    assert_eq!(run.irq_rises, 0);
}

#[test]
fn exhaustive_cases_icarus() {
    for ram in BUILDS {
        isa::exhaustive_verilog(Simulator::Icarus, ram).assert_passed();
    }
}

#[test]
fn exhaustive_cases_verilator() {
    for ram in BUILDS {
        isa::exhaustive_verilog(Simulator::Verilator, ram).assert_passed();
    }
}

#[test]
fn block_transfers_icarus() {
    for ram in BUILDS {
        isa::block_transfer_verilog(Simulator::Icarus, ram).assert_passed();
    }
}

#[test]
fn block_transfers_verilator() {
    for ram in BUILDS {
        isa::block_transfer_verilog(Simulator::Verilator, ram).assert_passed();
    }
}

#[test]
fn random_traffic_all_simulators() {
    for ram in BUILDS {
        isa::random_rust(ram).assert_passed();
        isa::random_verilog(Simulator::Icarus, ram).assert_passed();
        isa::random_verilog(Simulator::Verilator, ram).assert_passed();
    }
}

#[test]
fn the_random_traffic_rings_both_doorbells() {
    // The long random run (HDL against the model every clock) reaches the
    // doorbells: the DSP rings the PC with the IRQ enabled, and the PC
    // rings the DSP. The trace isa_doorbell shows one of each.
    let ops = isa::random_ops(isa::LONG_RANDOM.0, isa::LONG_RANDOM.1);
    let (r, run) = isa::check_rust(IsaRam::Internal, "doorbells", &ops, ops.len() as u64);
    r.assert_passed();
    assert!(
        run.irq_rises >= 5 && run.bells_to_dsp >= 5,
        "IRQ rises {}, DSP bells {}",
        run.irq_rises,
        run.bells_to_dsp
    );
    eprintln!(
        "IRQ rises {}, DSP bells {}",
        run.irq_rises, run.bells_to_dsp
    );
}

#[test]
fn same_clock_writes_follow_the_rule_everywhere() {
    let r = isa::collision_check(None);
    assert!(r.expected > 100);
    r.assert_passed();
    isa::collision_check(Some(Simulator::Icarus.into())).assert_passed();
    isa::collision_check(Some(Simulator::Verilator.into())).assert_passed();
}

#[test]
fn a_wrong_read_is_caught() {
    // The comparison itself must be able to fail.
    let ops = [Op::DspWrite { addr: 3, data: 7 }, Op::DspRead { addr: 3 }];
    for ram in BUILDS {
        let run = isa::run_rust(ram, isa::TEST_BASE, &ops, None);
        let mut want = isa::expected(ram, isa::TEST_BASE, &ops);
        assert!(isa::same(&run.observations[0], &want[0]), "{ram:?}");
        want[0] = Observation::Dsp { data: 8 };
        assert!(!isa::same(&run.observations[0], &want[0]));
    }
}

#[test]
fn the_sram_model_flags_a_short_write_pulse() {
    // The external build's chip model checks WE# timing; prove it can object.
    use motionhdl_model::isa_bridge::SramPins;
    let mut chip = isa::DualPortSram::new();
    let idle = motionhdl_model::isa_bridge::IsaPins::idle(0);
    let read = SramPins {
        addr: 5,
        we_n: true,
        ..Default::default()
    };
    let setup = SramPins {
        d_oe: true,
        d_out: 0x1234,
        oe_n: true,
        ..read
    };
    let pulse = SramPins {
        we_n: false,
        ..setup
    };
    assert!(chip.edge(1, &idle, read).is_empty());
    assert!(chip.edge(3, &idle, setup).is_empty());
    assert!(chip.edge(4, &idle, pulse).is_empty());
    let bad = chip.edge(5, &idle, setup);
    assert!(
        bad.iter().any(|b| b.contains("WE# pulse of 1 clocks")),
        "{bad:?}"
    );
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]
        /// Random ISA cycles (other cards' ports, DMA cycles, every command
        /// length and phase) with DSP traffic between them: rust-hdl vs
        /// the cycle model every clock, every read vs the transaction model.
        #[test]
        fn random_bus_traffic(seed in any::<u64>(), n in 1usize..60, external in any::<bool>()) {
            let ram = if external { IsaRam::External } else { IsaRam::Internal };
            let ops = isa::random_ops(seed, n);
            let (r, run) = isa::check_rust(ram, "proptest", &ops, ops.len() as u64);
            prop_assert!(r.failures.is_empty(), "{ram:?} seed {seed:#x} n {n}: {:?}", r.failures);
            prop_assert!(run.clocks > 0);
        }
    }
}
