//! A broken copy's bounded check, run as SymbiYosys runs it but in two
//! processes instead of five: one yosys for sby's three scripts (read and
//! `prep`, its formal preparation, the SMT-LIB 2 export) and one
//! yosys-smtbmc. A break on a block took 2.4 s through sby, most of it
//! starting Python and WebAssembly per step, and 1.4 s here.
//! `tests/formal.rs` holds [`SBY_STEPS`] to what the installed sby writes,
//! so that a break fails under the proof's own flow.

use super::sby::{self, Mode, Outcome, Tools, Verdict};
use super::spec::ProofSpec;
use crate::CliError;
use std::path::Path;
use std::process::Command;

/// The commands sby 0.70 runs after a proof's `[script]` for an smtbmc
/// engine (its model/design.ys, design_prep.ys and design_smt2.ys), less
/// the files it writes and reads between them.
pub const SBY_STEPS: &str = "\
hierarchy -smtcheck
rename -witness
scc -select; simplemap; select -clear
memory_nordff
async2sync
chformal -assume -early
opt_clean
formalff -setundef -clk2ff -ff2anyinit -hierarchy
chformal -live -fair -cover -remove
opt_clean
check
setundef -undriven -anyseq
opt -fast
rename -witness
opt_clean
hierarchy -smtcheck
delete */t:$print
formalff -assume
dffunmap
stat
";

/// The yosys script of `spec`'s broken copy in `files` keeping only
/// `label`: the proof's script, sby's steps, the SMT-LIB 2 model.
pub fn yosys_script(spec: &ProofSpec, files: &[String], label: &str) -> String {
    format!(
        "{}{SBY_STEPS}write_smt2 -wires design.smt2\n",
        sby::script(spec, files, Mode::Only(label))
    )
}

/// Checks `label` on the broken copy staged in `dir` (by
/// [`super::stage`]) from reset to `depth` steps, as sby's bmc mode does.
pub fn run(
    tools: &Tools,
    dir: &Path,
    spec: &ProofSpec,
    files: &[String],
    label: &str,
    depth: u32,
) -> Result<Outcome, CliError> {
    let started = std::time::Instant::now();
    std::fs::write(dir.join("bmc.ys"), yosys_script(spec, files, label))
        .map_err(|e| CliError::failure(format!("cannot write bmc.ys: {e}")))?;
    let mut yosys = Command::new(&tools.yosys);
    yosys.args(["-q", "-l", "yosys.log", "-s", "bmc.ys"]);
    if let Err(e) = crate::tool::run(&mut yosys, "yosys", dir, "yosys.log") {
        return Ok(outcome(
            Verdict::Error { message: e.message },
            None,
            started,
        ));
    }
    let mut smtbmc = Command::new(&tools.smtbmc);
    smtbmc
        .args(["-s", "yices", "--presat", "--unroll", "--noprogress", "-t"])
        .arg(depth.to_string())
        .args(["--dump-vcd", "trace.vcd", "design.smt2"]);
    smtbmc.env("PATH", sby::solver_path(tools));
    crate::tool::run_status(&mut smtbmc, "smtbmc", dir)?;
    let log = std::fs::read_to_string(dir.join("smtbmc.stdout")).unwrap_or_default();
    let trace = Some(dir.join("trace.vcd")).filter(|p| p.is_file());
    Ok(outcome(verdict(&log), trace, started))
}

fn outcome(
    verdict: Verdict,
    trace: Option<std::path::PathBuf>,
    started: std::time::Instant,
) -> Outcome {
    Outcome {
        verdict,
        covers_reached: Vec::new(),
        covers_missed: Vec::new(),
        trace,
        seconds: started.elapsed().as_secs_f64(),
    }
}

/// The verdict from yosys-smtbmc's output: the assertions it names
/// failing, and its status line.
pub fn verdict(log: &str) -> Verdict {
    let labels = sby::failed_labels(log.lines());
    let status = log
        .lines()
        .rev()
        .find_map(|l| l.split_once("Status: "))
        .map(|(_, s)| s.trim().to_ascii_uppercase());
    match status.as_deref() {
        Some("FAILED") if !labels.is_empty() => Verdict::Failed { labels },
        Some("PASSED") => Verdict::Proved { k: 0 },
        _ => Verdict::Error {
            message: format!("yosys-smtbmc ended without a verdict:\n{log}"),
        },
    }
}
