//! `motionhdl`: generate the gateware's Verilog, traces and firmware headers,
//! and verify the HDL against the bit-accurate model.

use clap::{Parser, Subcommand};
use motionhdl::output::generated_dir;
use motionhdl::progress::Stage;
use motionhdl::{artifacts, config_file, output, verify, CliError};
use motionhdl_testbench::scenarios;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "motionhdl",
    version,
    about = "FPGA half of a multi-axis motion controller: Verilog, VCD traces and firmware headers from rust-hdl, checked against a bit-accurate model",
    long_about = None,
    after_help = "Start with `motionhdl generate` (writes ./generated) and `motionhdl verify`.\n\
                  Exit codes: 0 success, 1 a check or the work failed, 2 bad input (nothing written)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write every generated file: Verilog (blocks, top, board wrapper), VCD
    /// traces with GTKWave save files, C headers and their self-test, the
    /// Rust register module, SVD, JSON and Markdown register maps, pin and
    /// timing constraints, a FuseSoC core, and MANIFEST.sha256.
    ///
    /// The output directory is replaced as a whole, in one atomic swap, and
    /// only once every file has been produced: on any error nothing is
    /// written. It is replaced only while it holds a previous motionhdl
    /// output and nothing else (see MANIFEST.sha256); the current, home and
    /// root directories, a repository root and the configuration file's
    /// directory are refused. Without --config the built-in default is used
    /// (4 axes, 28-bit counters, 50 MHz clock).
    Generate {
        /// Output directory: new, empty, or a previous motionhdl output.
        #[arg(long, default_value = "generated")]
        out: PathBuf,
        /// Configuration file (TOML): axes (1..=16), counter_width (8..=32),
        /// clock_hz (1000000..=400000000), isa_ram ("internal" or
        /// "external"), counter_* build options, input_filter_us
        /// (1..=50000), gpio_inputs and gpio_outputs (0..=16), servo_dac
        /// (true: the servo card's top, with the DAC and the servo tick),
        /// board (one that must take every pin). Missing keys keep their
        /// defaults.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Write even though the directory holds files motionhdl did not
        /// write, or edited ones: motionhdl's own files are replaced, every
        /// other file is kept as it is; refused where one is in the way.
        #[arg(long)]
        force: bool,
        /// Leave out the scenario traces (vcd/): their simulation of the
        /// whole controller is most of generate's time. The directory then
        /// holds exactly the other files; a run without it writes them again.
        #[arg(long)]
        no_traces: bool,
    },
    /// Run the exhaustive model-vs-HDL checks and print covered/expected per check.
    ///
    /// The rust-hdl blocks are stepped directly and compared with the model on
    /// every input (and every state × input for clocked blocks); the generated
    /// Verilog runs the same vectors in Icarus Verilog and Verilator when they
    /// are on PATH. Then SymbiYosys proves the properties of formal/*.sv on
    /// the generated Verilog (k-induction) and reaches their covers; a
    /// failure keeps the counterexample as a VCD with a GTKWave save file.
    /// Exits 1 on any mismatch or unproved property, or on a skipped check
    /// when CI is set.
    Verify {
        /// Only the rust-hdl checks; do not run Icarus Verilog or Verilator.
        #[arg(long)]
        no_external: bool,
        /// Only this group of checks (repeatable): selector, counter,
        /// quadrature_core, ls688, isa_bridge, fsmc_bridge,
        /// motion_controller, pulse_generator, safety_io, servo_dac,
        /// netlist, formal (the SymbiYosys proofs of formal/*.sv).
        #[arg(long, value_name = "GROUP")]
        only: Vec<String>,
        /// The long scale: the long random runs and the wide instances at
        /// their full size (docs/testing.md), and the long formal proofs
        /// (minutes each).
        #[arg(long)]
        long: bool,
    },
    /// Measure simulation throughput of the default 4×28 counter bank and
    /// of the default top (motion_controller: 4 axes, 28-bit counters,
    /// shared RAM inside).
    ///
    /// Prints clock cycles per second for the model, the rust-hdl block
    /// stepped directly, and the generated Verilog in Icarus Verilog and
    /// Verilator (when on PATH; compilation not timed). The top's engines
    /// all run one deterministic pin stimulus (FSMC and ISA cycles, encoder
    /// motion); its table also says whether each engine's output-pin
    /// checksum equals the model's. A measurement, not a check.
    Bench {
        /// Clock cycles per engine. Counter bank: the model runs 10×, the
        /// rust-hdl block and Icarus 1/10, Verilator 10×. Top: the model and
        /// Verilator 5×, the rust-hdl top 1/20, Icarus 1/100.
        #[arg(long, default_value_t = 1_000_000,
              value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
        cycles: u64,
    },
    /// Synthesise, place and route the board-level top with yosys and nextpnr.
    ///
    /// Generates the Verilog for the configuration into a scratch directory,
    /// runs yosys (synth_ice40 / synth_ecp5) and nextpnr with the generated
    /// pin constraints (the board wrapper `motion_controller_board` as top),
    /// and prints logic cells / LUTs, FFs, carry cells, RAM blocks, I/O and
    /// Fmax per clock. A measurement: exits 0 even when Fmax misses the
    /// clock. Exit 2 when yosys or nextpnr is not on PATH.
    Synth {
        /// ice40-hx8k (iCE40 HX8K CT256) or ecp5-25k (LFE5U-25F CABGA256).
        #[arg(long, default_value = "ice40-hx8k")]
        target: String,
        /// Configuration file (TOML), as for `generate`.
        #[arg(long)]
        config: Option<PathBuf>,
        /// nextpnr placement seed (0..=2147483647, nextpnr's int).
        #[arg(long, default_value_t = 1,
              value_parser = clap::value_parser!(u64).range(0..=i32::MAX as u64))]
        seed: u64,
        /// Every block alone (no pins) and then the board top: one table row each.
        #[arg(long)]
        all_blocks: bool,
        /// Run the board top without pin constraints.
        #[arg(long)]
        no_pins: bool,
        /// Leave the run's files in this new or empty directory: the
        /// Verilog and pin file, yosys's netlist.json and log, nextpnr's
        /// routed.json, report.json and log.
        #[arg(long, conflicts_with_all = ["sweep", "all_blocks"])]
        keep: Option<PathBuf>,
        /// A QoR sweep: every block alone, then the board top at each of
        /// `--axes`, on each of `--targets` and `--seeds`, as one Markdown
        /// table (a design that does not fit is packed only and its row says
        /// how much logic it needs). Hours for the full default sweep.
        #[arg(long, conflicts_with_all = ["all_blocks", "no_pins", "seed", "target"])]
        sweep: bool,
        /// With --sweep: axis counts of the board top (each 1..=16).
        #[arg(long, default_value = "1,4,8,16", requires = "sweep")]
        axes: String,
        /// With --sweep: nextpnr seeds (each 0..=2147483647).
        #[arg(long, default_value = "1,2,3", requires = "sweep")]
        seeds: String,
        /// With --sweep: targets, from ice40-hx8k and ecp5-25k.
        #[arg(long, default_value = "ice40-hx8k,ecp5-25k", requires = "sweep")]
        targets: String,
        /// With --sweep: leave out the rows of the blocks alone.
        #[arg(long, requires = "sweep")]
        no_blocks: bool,
        /// With --sweep: write the table, with the commit measured, into
        /// this Markdown file between its sweep markers (or appended, in a
        /// section of its own); the rest of the file is kept as it is.
        #[arg(long, requires = "sweep")]
        write: Option<PathBuf>,
    },
    /// Write one named scenario trace as a VCD file for GTKWave.
    #[command(after_help = scenario_help())]
    Trace {
        /// Scenario name (see the list below).
        name: String,
        /// Output VCD file; a GTKWave save file (.gtkw) is written beside it.
        /// An existing file is replaced only if motionhdl wrote it.
        #[arg(long)]
        out: PathBuf,
        /// Configuration file (TOML), as for `generate`; sets the clock period.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Replace the trace or save file even if motionhdl did not write it.
        #[arg(long)]
        force: bool,
    },
}

fn scenario_help() -> String {
    let mut s = String::from("Scenarios:\n");
    for sc in scenarios::SCENARIOS {
        s.push_str(&format!("  {}: {}\n", sc.name, sc.summary));
    }
    s
}

fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Generate {
            out,
            config,
            force,
            no_traces,
        } => {
            let options = generated_dir::Options {
                force,
                config: config.as_deref(),
            };
            let config = config_file::load(config.as_deref())?;
            // Refused before the work, so a wrong --out costs no time.
            generated_dir::check(&out, options)?;
            let traces = if no_traces {
                artifacts::Traces::Leave
            } else {
                artifacts::Traces::Write
            };
            let files: Vec<(PathBuf, Vec<u8>)> = artifacts::with_traces(&config, traces)
                .into_iter()
                .map(|a| (a.path, a.contents))
                .collect();
            let written = generated_dir::replace(&out, &files, options)?;
            println!(
                "wrote {} files to {} ({} axes, {}-bit counters, {} Hz){}",
                files.len() + 1,
                out.display(),
                config.axes(),
                config.counter_width(),
                config.clock_hz(),
                match written.kept {
                    0 => String::new(),
                    n => format!("; kept {n} file(s) motionhdl did not write"),
                }
            );
            Ok(())
        }
        Command::Verify {
            no_external,
            only,
            long,
        } => {
            if long {
                // The checks read their sizes from the scale
                // (motionhdl_testbench::scale); set before any thread starts.
                std::env::set_var(motionhdl_testbench::scale::LONG_VAR, "1");
            }
            let verified = verify::run(!no_external, &only, long)?;
            let reports = &verified.checks;
            if !reports.is_empty() {
                print!("{}", verify::table(reports));
            }
            let failed: Vec<_> = reports.iter().filter(|r| !r.acceptable()).collect();
            for r in &failed {
                for f in &r.failures {
                    eprintln!("{} / {}: {f}", r.block, r.check);
                }
            }
            if !verified.proofs.is_empty() {
                if !reports.is_empty() {
                    println!();
                }
                print!("{}", motionhdl::formal::table(&verified.proofs));
            }
            if let Some(why) = &verified.proofs_skipped {
                eprintln!("formal proofs skipped: {why}");
            }
            let proofs_failed = motionhdl::formal::failures(&verified.proofs);
            for f in &proofs_failed {
                eprintln!("{f}");
            }
            let unproved = verified.proofs.iter().filter(|p| !p.passed()).count();
            if failed.is_empty() && unproved == 0 {
                Ok(())
            } else {
                Err(CliError::failure(format!(
                    "{} of {} checks and {unproved} of {} proofs failed",
                    failed.len(),
                    reports.len(),
                    verified.proofs.len()
                )))
            }
        }
        Command::Bench { cycles } => {
            use motionhdl_testbench::bench;
            use motionhdl_testbench::verilog_sim::Simulator;
            let bank = [
                (Simulator::Icarus, cycles / 10 + 1),
                (Simulator::Verilator, cycles * 10),
            ];
            let mut rows = vec![
                Stage::run("bench counter_bank: model", || bench::model(cycles * 10)),
                Stage::run("bench counter_bank: rust-hdl", || {
                    bench::rust_hdl(cycles / 10 + 1)
                }),
            ];
            rows.extend(measured("counter_bank", bank, bench::verilog));
            print_bench(
                "counter_bank 4 axes × 28 bits, random encoder and bus stimulus",
                &rows,
            );
            // The whole default top under one pin stimulus.
            let top = [
                (Simulator::Icarus, cycles / 100 + 1),
                (Simulator::Verilator, cycles * 5),
            ];
            let mut rows = vec![
                Stage::run("bench motion_controller: model", || {
                    bench::top_model(cycles * 5)
                }),
                Stage::run("bench motion_controller: rust-hdl", || {
                    bench::top_rust_hdl(cycles / 20 + 1)
                }),
            ];
            rows.extend(measured("motion_controller", top, bench::top_verilog));
            let c = bench::top_config();
            println!();
            print_bench(
                &format!(
                    "motion_controller {} axes × {} bits, RAM {}: FSMC and ISA cycles, encoder motion",
                    c.axes(),
                    c.counter_width(),
                    c.isa_ram().name()
                ),
                &rows,
            );
            Ok(())
        }
        Command::Synth {
            sweep: true,
            config,
            axes,
            seeds,
            targets,
            no_blocks,
            write,
            ..
        } => {
            let sweep_args = SweepArgs {
                axes,
                seeds,
                targets,
                no_blocks,
                write,
            };
            run_sweep(config, sweep_args)
        }
        Command::Synth {
            target,
            config,
            seed,
            all_blocks,
            no_pins,
            keep,
            ..
        } => {
            use motionhdl::synth;
            let target = synth::Target::from_name(&target)?;
            if let Some(dir) = &keep {
                synth::check_keep_dir(dir)?;
            }
            let config = config_file::load(config.as_deref())?;
            let tools = synth::find_tools(target)?;
            let freq = config.clock_hz() as f64 / 1e6;
            let mut board = synth::board_design(&config, target);
            if no_pins {
                board.pins = None;
            }
            println!(
                "target {} ({}), {} axes, {}-bit counters, {} MHz, isa_ram = \"{}\", seed {seed}",
                target.name(),
                target.device(),
                config.axes(),
                config.counter_width(),
                freq,
                config.isa_ram().name()
            );
            println!(
                "tools: {} ({}) and {} ({})",
                tools.yosys.display(),
                motionhdl::tool::version(&tools.yosys, "yosys")?,
                tools.nextpnr.display(),
                motionhdl::tool::version(&tools.nextpnr, "nextpnr")?
            );
            if all_blocks {
                println!("{}", synth::table_header(target));
                for design in synth::all_blocks(&config).iter().chain([&board]) {
                    let r = synth::synthesize(design, target, &tools, freq, seed, None)?;
                    println!("{}", synth::row(&r, target));
                }
                return Ok(());
            }
            if board.pins.is_none() && !no_pins {
                println!(
                    "note: {} pins do not fit the {} pin map; running without pin constraints",
                    motionhdl::board::ports(&config)
                        .iter()
                        .map(|p| p.width)
                        .sum::<u32>(),
                    target.name()
                );
            }
            let r = synth::synthesize(&board, target, &tools, freq, seed, keep.as_deref())?;
            println!(
                "top: {} ({})",
                r.top,
                if r.pinned {
                    "pins from the generated constraints"
                } else {
                    "no pin constraints"
                }
            );
            print!("{}", synth::describe(&r, target));
            Ok(())
        }
        Command::Trace {
            name,
            out,
            config,
            force,
        } => {
            let config = config_file::load(config.as_deref())?;
            let scenario = scenarios::find(&name).ok_or_else(|| {
                CliError::input(format!(
                    "unknown scenario `{name}`: allowed {}",
                    scenarios::names().join(", ")
                ))
            })?;
            // The GTKWave save file (and a plot) beside the trace, naming
            // it relatively.
            let gtkw = out.with_extension("gtkw");
            let svg = out.with_extension("svg");
            let mut paths = vec![out.as_path(), gtkw.as_path()];
            if scenario.plot {
                paths.push(svg.as_path());
            }
            output::check_files(&paths, force)?;
            let trace = scenario.trace(&config);
            let vcd_name = out
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let mut files = vec![
                (out.clone(), trace.to_vcd_string().into_bytes()),
                (gtkw.clone(), trace.to_gtkw(&vcd_name).into_bytes()),
            ];
            if let Some(plot) = trace.plot() {
                files.push((svg, plot.as_bytes().to_vec()));
            }
            output::write_files(&files, force)?;
            let written: Vec<String> = files.iter().map(|f| f.0.display().to_string()).collect();
            println!("wrote {} ({})", written.join(", "), scenario.summary);
            Ok(())
        }
    }
}

/// Runs each simulator's measurement, saying which could not run.
fn measured(
    design: &str,
    runs: [(motionhdl_testbench::verilog_sim::Simulator, u64); 2],
    measure: fn(
        motionhdl_testbench::verilog_sim::Simulator,
        u64,
    ) -> Result<motionhdl_testbench::bench::Throughput, String>,
) -> Vec<motionhdl_testbench::bench::Throughput> {
    let mut rows = Vec::new();
    for (sim, n) in runs {
        let run = Stage::run(format!("bench {design}: {}", sim.name()), || {
            measure(sim, n)
        });
        match run {
            Ok(t) => rows.push(t),
            Err(e) => println!(
                "{}: not measured: {}",
                sim.name(),
                e.lines().next().unwrap_or("")
            ),
        }
    }
    rows
}

/// One throughput table; the last column only where rows compare their
/// outputs with the model.
fn print_bench(title: &str, rows: &[motionhdl_testbench::bench::Throughput]) {
    let compares = rows.iter().any(|r| r.agrees.is_some());
    println!("{title}");
    println!(
        "{:<48} {:>12} {:>10} {:>14}{}",
        "engine",
        "cycles",
        "seconds",
        "cycles/s",
        if compares { "  outputs = model" } else { "" }
    );
    for r in rows {
        let agreement = match (compares, r.agrees) {
            (false, _) => "",
            (true, None) => "  (reference)",
            (true, Some(true)) => "  yes",
            (true, Some(false)) => "  NO",
        };
        println!(
            "{:<48} {:>12} {:>10.3} {:>14.0}{agreement}",
            r.engine,
            r.cycles,
            r.seconds,
            r.per_second()
        );
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("motionhdl: error: {e}");
            ExitCode::from(e.exit_code as u8)
        }
    }
}

/// The --sweep options, as given.
struct SweepArgs {
    axes: String,
    seeds: String,
    targets: String,
    no_blocks: bool,
    write: Option<PathBuf>,
}

/// `motionhdl synth --sweep`: each row printed as it completes, then the
/// table written into `--write`'s document.
fn run_sweep(config: Option<PathBuf>, args: SweepArgs) -> Result<(), CliError> {
    use motionhdl::{sweep, synth};
    let base = config_file::load(config.as_deref())?;
    let axes = sweep::parse_list("axes", &args.axes, 1..=16)?;
    let seeds = sweep::parse_list("seeds", &args.seeds, 0..=i32::MAX as u64)?;
    let targets = args
        .targets
        .split(',')
        .map(|t| {
            synth::Target::from_name(t.trim()).map_err(|_| {
                CliError::input(format!(
                    "--targets: `{t}` is not a target: use ice40-hx8k or ecp5-25k"
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(doc) = &args.write {
        sweep::check_document(doc)?;
    }
    for &t in &targets {
        synth::find_tools(t)?;
    }
    let plan = sweep::Plan {
        targets,
        axes: axes.iter().map(|&n| n as u32).collect(),
        seeds,
        blocks: !args.no_blocks,
    };
    let mut command = format!(
        "motionhdl synth --sweep --axes {} --seeds {} --targets {}",
        args.axes, args.seeds, args.targets
    );
    if args.no_blocks {
        command.push_str(" --no-blocks");
    }
    if let Some(c) = &config {
        command.push_str(&format!(" --config {}", c.display()));
    }
    // The commit as the runs start: the tree may change while they run.
    let commit = sweep::commit();
    print!("{}", sweep::header());
    let rows = sweep::run(&plan, &base, &mut |row| print!("{}", sweep::line(row)))?;
    if let Some(doc) = &args.write {
        sweep::write_into(doc, &sweep::section(&rows, &command, &commit))?;
        println!("wrote the table into {}", doc.display());
    }
    Ok(())
}
