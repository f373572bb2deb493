//! Interrupting `generate`, `trace` and `synth` at every step, and running
//! out of space: the path always holds the complete old or the complete new
//! output, and nothing is left beside it. The steps are driven by the test
//! hook `MOTIONHDL_TEST_HOOK` (see src/interrupt.rs), not by timing.

mod common;

use common::fs_state::{
    self, assert_refused, command, expected_quick_output, finish, names, put, run, tree,
};
use std::collections::BTreeMap;
use std::fs;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::Output;
use std::sync::OnceLock;

/// The steps of replacing an output directory, in order; the swap falls
/// between the second and the third.
const STEPS: [&str; 4] = [
    "generate-staging",
    "generate-staged",
    "generate-swapped",
    "generate-cleaning",
];

/// A directory holding the 2-axis output, to be replaced by the default:
/// a copy (`cp -a`, modes kept) of one real `generate` made once per run,
/// since every case starts from the same old output.
fn old_output() -> tempfile::TempDir {
    type Template = (tempfile::TempDir, BTreeMap<String, fs_state::Node>);
    static TEMPLATE: OnceLock<Template> = OnceLock::new();
    let (template, template_tree) = TEMPLATE.get_or_init(|| {
        let t = tempfile::tempdir().unwrap();
        fs::write(t.path().join("two.toml"), "axes = 2\n").unwrap();
        let o = run(
            t.path(),
            &[
                "generate",
                "--no-traces",
                "--out",
                "gen",
                "--config",
                "two.toml",
            ],
        );
        assert!(o.status.success(), "{}", fs_state::stderr(&o));
        let files = tree(t.path());
        (t, files)
    });
    let t = tempfile::tempdir().unwrap();
    let copied = std::process::Command::new("cp")
        .arg("-a")
        .arg(template.path().join("gen"))
        .arg(template.path().join("two.toml"))
        .arg(t.path())
        .status()
        .unwrap();
    assert!(copied.success(), "cp -a of the old output");
    assert_eq!(&tree(t.path()), template_tree);
    t
}

fn generate_with_hook(dir: &Path, hook: &str) -> Output {
    let mut c = command(dir, &["generate", "--no-traces", "--out", "gen"]);
    c.env("MOTIONHDL_TEST_HOOK", hook);
    finish(c)
}

#[test]
fn a_signal_at_any_step_leaves_the_old_or_the_new_output_and_nothing_else() {
    let (old, new) = (
        expected_quick_output("axes = 2\n"),
        expected_quick_output(""),
    );
    let mut cases = 0;
    for (i, step) in STEPS.iter().enumerate() {
        for (action, code, name) in [("sigint", 130, "SIGINT"), ("sigterm", 143, "SIGTERM")] {
            let t = old_output();
            let o = generate_with_hook(t.path(), &format!("{step}={action}"));
            let swapped = i >= 2;
            let state = if swapped {
                "gen already holds the complete new output"
            } else {
                "gen is as it was"
            };
            assert_refused(&o, code, &[&format!("interrupted by {name}: {state}")]);
            let got = tree(&t.path().join("gen"));
            assert!(
                got == if swapped { new.clone() } else { old.clone() },
                "{step} {action}"
            );
            assert_eq!(
                names(t.path()),
                ["gen", "two.toml"],
                "{step} {action}: leftovers"
            );
            cases += 1;
        }
    }
    assert_eq!(cases, 8);
}

#[test]
fn a_kill_at_any_step_leaves_a_whole_output_and_the_next_run_sweeps_up() {
    let (old, new) = (
        expected_quick_output("axes = 2\n"),
        expected_quick_output(""),
    );
    for (i, step) in STEPS.iter().enumerate() {
        let t = old_output();
        let o = generate_with_hook(t.path(), &format!("{step}=sigkill"));
        assert_eq!(
            o.status.signal(),
            Some(9),
            "{step}: {}",
            fs_state::stderr(&o)
        );
        let got = tree(&t.path().join("gen"));
        assert!(
            got == if i >= 2 { new.clone() } else { old.clone() },
            "{step}"
        );
        let left: Vec<String> = names(t.path())
            .into_iter()
            .filter(|n| n.starts_with(".motionhdl-staging."))
            .collect();
        assert_eq!(left.len(), 1, "{step}: the staging directory a kill leaves");
        // Leftovers of the manifest-less versions too, of a process that is gone.
        let dead = (1 << 22) + 1; // above Linux's pid_max ceiling
        put(
            t.path(),
            &[
                (&format!(".gen.tmp-{dead}/x.v"), "x"),
                (&format!(".gen.old-{dead}/y"), "y"),
            ],
        );
        let o = run(t.path(), &["generate", "--no-traces", "--out", "gen"]);
        assert_eq!(o.status.code(), Some(0), "{step}: {}", fs_state::stderr(&o));
        assert_eq!(tree(&t.path().join("gen")), new, "{step}");
        assert_eq!(names(t.path()), ["gen", "two.toml"], "{step}: not swept");
    }
}

#[test]
fn a_staging_name_of_a_live_old_style_run_is_left_alone() {
    let t = tempfile::tempdir().unwrap();
    let me = std::process::id();
    put(t.path(), &[(&format!(".gen.tmp-{me}/x.v"), "x")]);
    assert!(run(t.path(), &["generate", "--no-traces", "--out", "gen"])
        .status
        .success());
    assert_eq!(names(t.path()), [format!(".gen.tmp-{me}"), "gen".into()]);
}

#[test]
fn trace_interrupted_before_its_renames_leaves_the_old_files() {
    let t = tempfile::tempdir().unwrap();
    let args = ["trace", "pulse_reversal", "--out", "p.vcd"];
    assert!(run(
        t.path(),
        &["trace", "pulse_mode_selector", "--out", "p.vcd"]
    )
    .status
    .success());
    let before = tree(t.path());
    let mut c = command(t.path(), &args);
    c.env("MOTIONHDL_TEST_HOOK", "write-staged=sigint");
    let o = finish(c);
    assert_refused(
        &o,
        130,
        &["interrupted by SIGINT: p.vcd and p.gtkw left as they were"],
    );
    assert_eq!(tree(t.path()), before);
    // A kill between the two renames: each file whole, and swept next time.
    let mut c = command(t.path(), &args);
    c.env("MOTIONHDL_TEST_HOOK", "write-renamed=sigkill");
    let o = finish(c);
    assert_eq!(o.status.signal(), Some(9));
    assert!(run(t.path(), &args).status.success());
    assert_eq!(names(t.path()), ["p.gtkw", "p.vcd"]);
}

#[test]
fn trace_on_a_full_disk_fails_with_the_old_file_intact() {
    let t = tempfile::tempdir().unwrap();
    let args = ["trace", "system", "--out", "s.vcd"];
    put(
        t.path(),
        &[(
            "s.vcd",
            "$comment Generated by motionhdl 0.1.0 -- do not edit $end\n",
        )],
    );
    let before = tree(t.path());
    let mut c = command(t.path(), &args);
    // A file-size limit makes every write past 64 KiB fail as a full disk
    // does; SIGXFSZ ignored so that the write returns the error.
    unsafe {
        c.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: 64 << 10,
                rlim_max: 64 << 10,
            };
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let o = fs_state::finish(c);
    assert_refused(&o, 1, &["cannot write", "s.vcd", "File too large"]);
    assert_eq!(tree(t.path()), before);
}

/// A fake tool for `synth`: a shell script that records its PID, then runs
/// `body`.
fn fake_tool(dir: &Path, name: &str, body: &str) {
    use std::os::unix::fs::PermissionsExt;
    let p = dir.join(name);
    fs::write(
        &p,
        format!(
            "#!/bin/sh\necho $$ > \"{}/{name}.pid\"\n{body}\n",
            dir.display()
        ),
    )
    .unwrap();
    fs::set_permissions(&p, fs::Permissions::from_mode(0o755)).unwrap();
}

/// Runs `synth` with fake yosys and nextpnr first on PATH and TMPDIR in a
/// fresh directory; returns the output and what TMPDIR holds afterwards.
fn synth_with(yosys: &str) -> (Output, Vec<String>, Option<u32>) {
    let t = tempfile::tempdir().unwrap();
    let (bin, tmp) = (t.path().join("bin"), t.path().join("tmp"));
    fs::create_dir_all(&bin).unwrap();
    fs::create_dir_all(&tmp).unwrap();
    fake_tool(&bin, "yosys", yosys);
    fake_tool(&bin, "nextpnr-ice40", "exit 1");
    fs::write(t.path().join("one.toml"), "axes = 1\n").unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut c = command(t.path(), &["synth", "--config", "one.toml"]);
    c.env("PATH", path).env("TMPDIR", &tmp);
    let o = finish(c);
    let pid = fs::read_to_string(bin.join("yosys.pid"))
        .ok()
        .and_then(|s| s.trim().parse().ok());
    (o, names(&tmp), pid)
}

#[test]
fn synth_removes_its_scratch_directory_on_a_signal_and_stops_the_tool() {
    for (sig, code, name) in [("INT", 130, "SIGINT"), ("TERM", 143, "SIGTERM")] {
        // The tool signals motionhdl, then waits for ever unless stopped.
        let (o, tmp, pid) = synth_with(&format!("kill -{sig} $PPID\nexec sleep 600"));
        assert_refused(
            &o,
            code,
            &[&format!("interrupted by {name}: yosys stopped")],
        );
        assert!(tmp.is_empty(), "{name}: scratch left: {tmp:?}");
        let pid = pid.expect("the fake yosys ran");
        assert!(
            !Path::new(&format!("/proc/{pid}")).exists(),
            "{name}: yosys still runs"
        );
    }
}

#[test]
fn synth_removes_its_scratch_directory_when_a_tool_fails() {
    let (o, tmp, _) = synth_with("echo 'ERROR: broken' >&2\nexit 3");
    assert_refused(&o, 1, &["yosys failed", "ERROR: broken"]);
    assert!(tmp.is_empty(), "scratch left: {tmp:?}");
}
