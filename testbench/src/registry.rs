//! Every check `motionhdl verify` runs, in one list: each block's checks
//! module contributes its `all`, and the post-synthesis netlist runs are
//! listed here (they reuse the blocks' Verilog checks on a netlist target).

use crate::checks::{
    counter_bank, counter_channel, fsmc_bridge, input_filter, isa_bridge, ls153, ls688,
    motion_controller, move_engine, pulse_bank, pulse_generator, pulse_mode_selector,
    quadrature_core, safety_io, servo_dac,
};
use crate::CheckReport;

/// One group of checks: a block's checks modules (the selector group holds
/// the 74LS153 and the pulse-mode selector, the counter group the input
/// filter, the channel core and the bank), or the netlist runs.
pub struct Group {
    pub name: &'static str,
    pub run: fn(bool) -> Vec<CheckReport>,
}

/// Every group, in the order `motionhdl verify` prints them. The netlist
/// runs need the external tools, so they run only with `external`.
pub const GROUPS: [Group; 11] = [
    Group {
        name: "selector",
        run: |external| [ls153::all(external), pulse_mode_selector::all(external)].concat(),
    },
    Group {
        name: "counter",
        run: |external| {
            [
                input_filter::all(external),
                counter_channel::all(external),
                counter_bank::all(external),
            ]
            .concat()
        },
    },
    Group {
        name: "quadrature_core",
        run: quadrature_core::all,
    },
    Group {
        name: "ls688",
        run: ls688::all,
    },
    Group {
        name: "isa_bridge",
        run: isa_bridge::all,
    },
    Group {
        name: "fsmc_bridge",
        run: fsmc_bridge::all,
    },
    Group {
        name: "motion_controller",
        run: motion_controller::all,
    },
    Group {
        name: "pulse_generator",
        run: |external| {
            [
                pulse_generator::all(external),
                move_engine::all(external),
                pulse_bank::all(external),
            ]
            .concat()
        },
    },
    Group {
        name: "safety_io",
        run: safety_io::all,
    },
    Group {
        name: "servo_dac",
        run: servo_dac::all,
    },
    Group {
        name: "netlist",
        run: netlist_group,
    },
];

fn netlist_group(external: bool) -> Vec<CheckReport> {
    if external {
        netlist_checks()
    } else {
        Vec::new()
    }
}

/// The names of the groups, for messages.
pub fn group_names() -> Vec<&'static str> {
    GROUPS.iter().map(|g| g.name).collect()
}

/// Runs every check (or only the groups named in `only`, when it is not
/// empty). `external` includes the generated-Verilog runs in Icarus
/// Verilog and Verilator, and each block's check on its post-synthesis
/// yosys netlist in Icarus.
pub fn run(external: bool, only: &[String]) -> Vec<CheckReport> {
    selected(only)
        .into_iter()
        .flat_map(|name| run_group(external, name))
        .collect()
}

/// The groups `only` names, in the registry's order; all when it is empty.
pub fn selected(only: &[String]) -> Vec<&'static str> {
    GROUPS
        .iter()
        .map(|g| g.name)
        .filter(|name| only.is_empty() || only.iter().any(|o| o == name))
        .collect()
}

/// Runs the group `name` (one of [`group_names`]).
pub fn run_group(external: bool, name: &str) -> Vec<CheckReport> {
    let group = GROUPS
        .iter()
        .find(|g| g.name == name)
        .unwrap_or_else(|| panic!("no group of checks named {name}"));
    (group.run)(external)
}

/// Runs every check.
pub fn all(external: bool) -> Vec<CheckReport> {
    run(external, &[])
}

/// Clocks of the counter bank's random stimulus run on its netlist (the
/// generated file runs 30 000 in Icarus and 10^7 in Verilator).
pub const COUNTER_BANK_CLOCKS: u64 = 30_000;

/// Clocks per width of the quadrature core's random run on its netlist (as
/// on the generated file).
pub const QUADRATURE_CLOCKS: u64 = 100_000;

/// The quadrature core runs: (width, seed), as on the generated file.
pub const QUADRATURE_RUNS: [(u32, u64); 2] = [(4, 0x9e37_79b9), (32, 0x2545_f491)];

/// Every block's Verilog check run on the block's post-synthesis netlist in
/// Icarus, with the vectors and expected results of the generated-file run
/// (shorter for the counter bank; see [`COUNTER_BANK_CLOCKS`]).
pub fn netlist_checks() -> Vec<CheckReport> {
    use crate::verilog_sim::{Simulator, Target};
    use motionhdl_model::{Config, IsaRam};
    let t = Target::netlist(Simulator::Icarus);
    let mut v = vec![
        ls153::ls153_verilog(t),
        pulse_mode_selector::selector_verilog(t),
        pulse_mode_selector::registered_verilog(t),
        ls688::ls688_verilog(t),
        counter_bank::verilog_long_run(t, COUNTER_BANK_CLOCKS),
    ];
    for (w, seed) in QUADRATURE_RUNS {
        v.push(quadrature_core::verilog_against_channel(
            t,
            w,
            QUADRATURE_CLOCKS,
            seed,
        ));
    }
    for ram in [IsaRam::Internal, IsaRam::External] {
        v.push(isa_bridge::exhaustive_verilog(t, ram));
        v.push(isa_bridge::block_transfer_verilog(t, ram));
        v.push(isa_bridge::random_verilog(t, ram));
    }
    v.push(isa_bridge::collision_check(Some(t)));
    v.push(fsmc_bridge::sweep_verilog(t));
    v.push(fsmc_bridge::random_verilog(t));
    v.push(safety_io::random_verilog(t, 20_000, 0x5afe_0004));
    v.push(servo_dac::random_verilog(t, 20_000, 0xdac0_0004));
    for ram in [IsaRam::Internal, IsaRam::External] {
        v.push(motion_controller::check_verilog(
            t,
            &Config::default().with_isa_ram(ram),
        ));
    }
    v
}
