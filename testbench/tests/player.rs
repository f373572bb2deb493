//! The generic pin-event player: it refuses a rig or stream it cannot
//! replay exactly, reads the peripherals' port headers, and what it
//! replays reaches the design (a broken peripheral shows in the reads).

use motionhdl_hdl::catalog;
use motionhdl_hdl::ports::PortDir;
use motionhdl_testbench::bfm::fsmc::{self, documented_timing, Op};
use motionhdl_testbench::checks::fsmc_bridge::{SLAVE_CLEAR_CLOCKS, TEST_SLAVE_V};
use motionhdl_testbench::checks::isa_bridge::SRAM_V;
use motionhdl_testbench::harness::require_tool;
use motionhdl_testbench::player::{ansi_ports, Peripheral, PinStream, Rig, Row};
use motionhdl_testbench::verilog_sim::Simulator;

fn fsmc_rig(slave: &str) -> Rig {
    let module = catalog::fsmc_bridge();
    let mut rig = Rig::new(&module, module.text.clone(), fsmc::CLOCK);
    rig.peripherals.push(Peripheral::new(
        "fsmc_test_slave",
        "fsmc_test_slave.v",
        slave,
    ));
    rig.sampled = vec!["d_oe".into(), "d_out".into()];
    rig
}

fn panic_message(f: impl FnOnce() + std::panic::UnwindSafe) -> String {
    let e = std::panic::catch_unwind(f).expect_err("must panic");
    e.downcast_ref::<String>()
        .cloned()
        .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

#[test]
fn the_peripherals_port_headers_are_read() {
    let sram = ansi_ports(SRAM_V, "isa_dual_port_sram");
    assert_eq!(sram.len(), 12);
    let d_in = sram.iter().find(|p| p.name == "ram_d_in").unwrap();
    assert_eq!((d_in.dir, d_in.width), (PortDir::Output, 16));
    let slave = ansi_ports(TEST_SLAVE_V, "fsmc_test_slave");
    assert_eq!(slave.len(), 13);
    assert!(slave.iter().all(|p| p.name != "clock" || p.width == 1));
    let msg = panic_message(|| {
        ansi_ports("module m (\n    input wire [3:1] x\n);\n", "m");
    });
    assert!(msg.contains("line 2") && msg.contains("[3:1]"), "{msg}");
}

#[test]
fn a_rig_it_cannot_wire_is_refused_naming_the_net() {
    let stream = fsmc::stream(&[Op::Reset], &documented_timing());
    // Two drivers: the bridge drives d_out, a tie too.
    let msg = panic_message(|| {
        let mut rig = fsmc_rig(TEST_SLAVE_V);
        rig.ties.push(("d_out".into(), 0));
        rig.testbench(&stream);
    });
    assert!(msg.contains("`d_out` has two drivers"), "{msg}");
    // Nothing drives the slave's reg_rdata input once the slave is gone.
    let msg = panic_message(|| {
        let mut rig = fsmc_rig(TEST_SLAVE_V);
        rig.peripherals.clear();
        rig.testbench(&stream);
    });
    assert!(
        msg.contains("`ram_rdata` is read but nothing drives it"),
        "{msg}"
    );
    let msg = panic_message(|| {
        let mut rig = fsmc_rig(TEST_SLAVE_V);
        rig.sampled.push("nonesuch".into());
        rig.testbench(&stream);
    });
    assert!(msg.contains("`nonesuch`"), "{msg}");
}

#[test]
fn a_stream_that_races_the_clock_is_refused() {
    let rig = fsmc_rig(TEST_SLAVE_V);
    let values = vec![0; fsmc::PINS.len()];
    let racing = |rows: Vec<Row>| PinStream {
        driven: fsmc::PINS.map(String::from).to_vec(),
        rows,
        end: 10_000,
    };
    // A drive on a rising edge (420 ticks = 10 ns).
    let on_edge = racing(vec![Row::Drive {
        at: fsmc::FIRST_EDGE_TICKS,
        values: values.clone(),
    }]);
    let msg = panic_message(|| {
        let _ = rig.play(Simulator::Icarus, &on_edge);
    });
    assert!(msg.contains("races a clock edge"), "{msg}");
    // A sample at the time of a drive.
    let same_time = racing(vec![Row::Drive { at: 5, values }, Row::Sample { at: 5 }]);
    let msg = panic_message(|| {
        let _ = rig.play(Simulator::Icarus, &same_time);
    });
    assert!(msg.contains("races a drive"), "{msg}");
}

/// A 32-bit register write and its read-back through the player: the
/// written value with the real slave, its complement with a slave whose
/// register file reads inverted (so what the player replays does reach
/// the design, and a wrong design shows).
#[test]
fn a_broken_peripheral_shows_in_the_replayed_reads() {
    if require_tool("iverilog").is_none() {
        return;
    }
    let ops = [
        Op::Reset,
        Op::Write32 {
            a: 0x10,
            data: 0x1234_5678,
        },
        Op::Read32 { a: 0x10 },
    ];
    let stream =
        fsmc::stream(&ops, &documented_timing()).delayed(SLAVE_CLEAR_CLOCKS * fsmc::CLOCK_TICKS);
    let reads = |slave: &str| {
        let samples = fsmc_rig(slave).play(Simulator::Icarus, &stream).unwrap();
        let obs = fsmc::observations(&samples).unwrap();
        assert_eq!(obs.len(), 2);
        assert!(obs.iter().all(|o| o.oe_setup && o.oe_end));
        (obs[0].data_end, obs[1].data_end)
    };
    assert_eq!(reads(TEST_SLAVE_V), (0x5678, 0x1234));
    let good = ": regs[read_word];";
    assert!(TEST_SLAVE_V.contains(good));
    let broken = TEST_SLAVE_V.replace(good, ": ~regs[read_word];");
    assert_eq!(reads(&broken), (!0x5678, !0x1234));
}
