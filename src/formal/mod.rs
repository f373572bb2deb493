//! Formal proofs of the generated Verilog (docs/formal.md): each file in
//! `formal/` wraps generated modules, ports only, and states properties
//! that SymbiYosys proves by k-induction for every input sequence. The
//! generated files are read as they are; a proof sees an internal register
//! only through yosys `expose`.

pub mod bmc;
pub mod in_top;
pub mod sby;
pub mod spec;

use crate::CliError;
use motionhdl_hdl::catalog::{self, VerilogModule};
use spec::{Break, ProofSpec, Uses};
use std::path::{Path, PathBuf};

/// Every proof file, by name (`formal/<name>.sv`).
const FILES: [(&str, &str); 7] = [
    (
        "pulse_mode_selector",
        include_str!("../../formal/pulse_mode_selector.sv"),
    ),
    (
        "pulse_generator",
        include_str!("../../formal/pulse_generator.sv"),
    ),
    ("counter_bank", include_str!("../../formal/counter_bank.sv")),
    ("safety_io", include_str!("../../formal/safety_io.sv")),
    ("fsmc_bridge", include_str!("../../formal/fsmc_bridge.sv")),
    ("isa_bridge", include_str!("../../formal/isa_bridge.sv")),
    (
        "motion_controller",
        include_str!("../../formal/motion_controller.sv"),
    ),
];

/// Every proof, read from its file's header, each with an `in_top` line
/// followed by its copy on the block inside the top.
pub fn proofs() -> Vec<ProofSpec> {
    let mut all = Vec::new();
    for (name, text) in FILES {
        let spec = spec::parse(name, text).unwrap_or_else(|e| panic!("{e}"));
        let in_top = spec.in_top.as_ref().map(|t| {
            let text = |u: &Uses| module(u).unwrap_or_else(|e| panic!("{e}")).text;
            let top = Uses {
                module: in_top::TOP.to_string(),
                args: t.args.clone(),
            };
            in_top::derive(&spec, &text(&spec.uses[0]), &text(&top))
                .unwrap_or_else(|e| panic!("{e}"))
        });
        all.push(spec);
        all.extend(in_top);
    }
    all
}

/// The generated module a `uses` line names, built by the catalog.
pub fn module(uses: &Uses) -> Result<VerilogModule, String> {
    let args = uses.args.as_slice();
    let bad = || {
        format!(
            "uses {} {:?}: unknown module or wrong arguments",
            uses.module, args
        )
    };
    Ok(match (uses.module.as_str(), args) {
        ("pulse_mode_selector", []) => catalog::pulse_mode_selector(),
        ("pulse_generator", []) => catalog::pulse_generator(),
        ("fsmc_bridge", []) => catalog::fsmc_bridge(),
        ("isa_bridge", []) => catalog::isa_bridge(motionhdl_model::IsaRam::Internal),
        ("quadrature_core", [w @ 2..=32]) => catalog::quadrature_core(*w),
        ("counter_bank", [a @ 1..=16, w @ 8..=32]) => catalog::counter_bank(*a, *w),
        ("safety_io", [a @ 1..=16, t @ 1..=65535]) => catalog::safety_io(*a, *t),
        ("motion_controller", [a @ 1..=16, w @ 8..=32]) => {
            catalog::motion_controller(&proof_top(*a, *w)?)
        }
        _ => return Err(bad()),
    })
}

/// The top a proof reads as `motion_controller <axes> <width>`: a 1 MHz
/// clock with the 8 µs input filter (a filter tick of 2 clocks, as the
/// safety block's own proof) and the external-RAM ISA build, so that the
/// solver meets neither the 12 500-clock tick nor the 1 K × 16 RAM.
fn proof_top(axes: u32, width: u32) -> Result<motionhdl_model::Config, String> {
    let config = motionhdl_model::Config::new(u64::from(axes), u64::from(width), 1_000_000)
        .and_then(|c| c.with_input_filter_us(8))
        .map_err(|e| e.to_string())?;
    Ok(config.with_isa_ram(motionhdl_model::IsaRam::External))
}

/// What `verify` prints for one proof.
#[derive(Clone, Debug)]
pub struct ProofReport {
    pub spec: ProofSpec,
    pub outcome: sby::Outcome,
    /// The scratch directory, kept when the proof did not pass.
    pub kept: Option<PathBuf>,
}

impl ProofReport {
    pub fn passed(&self) -> bool {
        matches!(self.outcome.verdict, sby::Verdict::Proved { .. })
            && self.outcome.covers_missed.is_empty()
            && self.outcome.covers_reached.len() == self.spec.covers.len()
    }
}

/// Writes the proof's files into `dir`: the modules it uses (with `broken`
/// applied to the one whose text holds it), its own file, `proof.sby`;
/// returns the modules' file names, in the order they are read.
pub fn stage(spec: &ProofSpec, dir: &Path, broken: Option<&Break>) -> Result<Vec<String>, String> {
    let mut files = Vec::new();
    let mut applied = false;
    for uses in &spec.uses {
        let m = module(uses)?;
        let mut text = m.text;
        if let Some(b) = broken {
            match text.matches(&b.from).count() {
                0 => {}
                1 => {
                    text = text.replacen(&b.from, &b.to, 1);
                    applied = true;
                }
                n => {
                    return Err(format!(
                        "break {}: `{}` is in {}.v {n} times",
                        b.label, b.from, m.name
                    ))
                }
            }
        }
        let file = format!("{}.v", m.name);
        std::fs::write(dir.join(&file), text).map_err(|e| e.to_string())?;
        files.push(file);
    }
    if let Some(b) = broken.filter(|_| !applied) {
        return Err(format!(
            "break {}: `{}` is in no module the proof reads",
            b.label, b.from
        ));
    }
    std::fs::write(dir.join(format!("{}.sv", spec.name)), &spec.text).map_err(|e| e.to_string())?;
    let mode = broken.map_or(sby::Mode::Full, |b| sby::Mode::Only(&b.label));
    std::fs::write(dir.join("proof.sby"), sby::sby_text(spec, &files, mode))
        .map_err(|e| e.to_string())?;
    Ok(files)
}

/// Runs one proof in a scratch directory, kept (with the counterexample
/// as `counterexample.vcd` and its `.gtkw`) when the proof does not pass.
pub fn prove(spec: &ProofSpec, tools: &sby::Tools) -> Result<ProofReport, CliError> {
    let dir = tempfile::Builder::new()
        .prefix(&format!("motionhdl-formal-{}-", spec.name))
        .tempdir()
        .map_err(|e| CliError::failure(format!("cannot make a scratch directory: {e}")))?;
    stage(spec, dir.path(), None).map_err(CliError::failure)?;
    let mut report = ProofReport {
        spec: spec.clone(),
        outcome: sby::run(tools, dir.path(), sby::Mode::Full)?,
        kept: None,
    };
    if !report.passed() {
        if let Some(trace) = &mut report.outcome.trace {
            let vcd = std::fs::read_to_string(&*trace).unwrap_or_default();
            let cex = dir.path().join("counterexample.vcd");
            std::fs::write(&cex, &vcd).map_err(|e| CliError::failure(e.to_string()))?;
            std::fs::write(
                dir.path().join("counterexample.gtkw"),
                sby::gtkw(&cex.to_string_lossy(), &vcd, &spec.top()),
            )
            .map_err(|e| CliError::failure(e.to_string()))?;
            *trace = cex;
        }
        report.kept = Some(dir.keep());
    }
    Ok(report)
}

/// Runs `spec` with one break applied and only its property kept, a
/// bounded search from reset as deep as the covers go (they reach every
/// antecedent) through [`bmc`]: the verdict a test expects to be a
/// failure of that property.
pub fn prove_broken(
    spec: &ProofSpec,
    broken: &Break,
    tools: &sby::Tools,
) -> Result<sby::Outcome, CliError> {
    let dir = tempfile::tempdir().map_err(|e| CliError::failure(e.to_string()))?;
    let files = stage(spec, dir.path(), Some(broken)).map_err(CliError::failure)?;
    let depth = spec.depth.max(spec.cover_depth);
    bmc::run(tools, dir.path(), spec, &files, &broken.label, depth)
}

/// The breaks a scale runs of `spec`: every one of a block's own proof;
/// of a proof inside the whole top (`<proof>_in_top`, about 9 s a break
/// against 1-4 s on the block alone), `in_top_breaks` of them spread over
/// its list, first and last included, or all when there are no more.
pub fn breaks_at_scale(spec: &ProofSpec, in_top_breaks: u64) -> Vec<&Break> {
    let n = spec.breaks.len();
    let keep = usize::try_from(in_top_breaks).unwrap_or(usize::MAX);
    if !spec.is_in_top() || keep >= n {
        return spec.breaks.iter().collect();
    }
    match keep {
        0 => Vec::new(),
        1 => vec![&spec.breaks[0]],
        _ => (0..keep)
            .map(|i| &spec.breaks[i * (n - 1) / (keep - 1)])
            .collect(),
    }
}

/// Runs every proof (the long ones too with `long`), one after another.
pub fn run(long: bool) -> Result<Vec<ProofReport>, CliError> {
    let tools = sby::find_tools()?;
    proofs()
        .iter()
        .filter(|p| long || !p.long)
        .map(|p| prove(p, &tools))
        .collect()
}

/// The table `verify` prints after the checks': one row per property,
/// the proof's own cells on its first.
pub fn table(reports: &[ProofReport]) -> String {
    let mut rows = Vec::new();
    for r in reports {
        let o = &r.outcome;
        // The instance the proof reads, as its `uses` lines name it: a
        // narrow one shows its axes and widths.
        let instance = r
            .spec
            .uses
            .iter()
            .map(|u| {
                std::iter::once(u.module.clone())
                    .chain(u.args.iter().map(u32::to_string))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect::<Vec<_>>()
            .join(" + ");
        let mut head = Some([
            r.spec.name.clone(),
            instance,
            format!("{}/{}", o.covers_reached.len(), r.spec.covers.len()),
            format!("{:.1} s", o.seconds),
        ]);
        for p in &r.spec.properties {
            let result = match &o.verdict {
                sby::Verdict::Proved { k } => format!("proved (k-induction, depth {k})"),
                sby::Verdict::Failed { labels } if labels.contains(p) => "FAILED".to_string(),
                sby::Verdict::Unproven { labels } if labels.contains(p) => {
                    format!("UNPROVEN (induction fails at depth {})", r.spec.depth)
                }
                sby::Verdict::Error { .. } => "ERROR".to_string(),
                _ => "not decided (another failed)".to_string(),
            };
            let [name, instance, covers, time] = head.take().unwrap_or_default();
            rows.push(vec![name, instance, p.clone(), result, covers, time]);
        }
    }
    crate::text::columns(
        &["proof", "instance", "property", "result", "covers", "time"],
        &rows,
        &[4, 5],
    )
}

/// What went wrong in the reports that did not pass, for standard error.
pub fn failures(reports: &[ProofReport]) -> Vec<String> {
    let mut out = Vec::new();
    for r in reports.iter().filter(|r| !r.passed()) {
        let name = &r.spec.name;
        if let sby::Verdict::Error { message } = &r.outcome.verdict {
            out.push(format!("formal / {name}: SymbiYosys error:\n{message}"));
        }
        for c in &r.outcome.covers_missed {
            out.push(format!("formal / {name}: cover {c} is never reached"));
        }
        if let Some(cex) = &r.outcome.trace {
            out.push(format!(
                "formal / {name}: counterexample {} (GTKWave: {})",
                cex.display(),
                cex.with_extension("gtkw").display()
            ));
        }
        if let Some(dir) = &r.kept {
            out.push(format!(
                "formal / {name}: SymbiYosys files kept in {}",
                dir.display()
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_proof_file_reads_and_names_modules_the_catalog_builds() {
        let all = proofs();
        let in_top = all.iter().filter(|p| p.is_in_top()).count();
        assert_eq!(all.len(), FILES.len() + in_top);
        assert!(in_top >= 1, "the counter bank's proof in the top");
        for p in &all {
            for u in &p.uses {
                module(u).unwrap_or_else(|e| panic!("formal/{}.sv: {e}", p.name));
            }
        }
    }

    #[test]
    fn an_in_top_proof_runs_a_spread_of_its_breaks_and_a_block_proof_all() {
        let all = proofs();
        let top = all.iter().find(|p| p.is_in_top()).unwrap();
        let block = all.iter().find(|p| p.name == "counter_bank").unwrap();
        let n = top.breaks.len();
        assert!(n >= 4, "{n} breaks");
        let labels = |b: Vec<&Break>| b.iter().map(|b| b.label.clone()).collect::<Vec<_>>();
        let three = labels(breaks_at_scale(top, 3));
        assert_eq!(three.len(), 3);
        assert_eq!(three[0], top.breaks[0].label);
        assert_eq!(three[2], top.breaks[n - 1].label);
        assert_ne!(three[1], three[0]);
        assert_ne!(three[1], three[2]);
        assert_eq!(breaks_at_scale(top, n as u64).len(), n);
        assert_eq!(breaks_at_scale(top, 99).len(), n);
        assert_eq!(breaks_at_scale(block, 3).len(), block.breaks.len());
    }

    #[test]
    fn every_break_applies_to_exactly_one_place() {
        let dir = tempfile::tempdir().unwrap();
        for p in proofs() {
            for b in &p.breaks {
                stage(&p, dir.path(), Some(b)).unwrap_or_else(|e| panic!("{}: {e}", p.name));
            }
        }
    }
}
