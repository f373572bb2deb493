//! `generate` and `trace` never destroy what a user has: every refusal, what
//! `--force` keeps, and the exact file-system state after each run.

mod common;

use common::fs_state::{
    self, assert_refused, expected_output, expected_quick_output, inode, names, put, run, tree,
    Node,
};
use std::fs;

#[test]
fn a_directory_of_foreign_files_is_refused_and_untouched() {
    let t = tempfile::tempdir().unwrap();
    put(
        t.path(),
        &[("mine/a.txt", "mine"), ("mine/sub/b.txt", "also mine")],
    );
    let before = tree(t.path());
    let o = run(t.path(), &["generate", "--no-traces", "--out", "mine"]);
    assert_refused(
        &o,
        2,
        &[
            "refusing to replace mine",
            "2 file(s) motionhdl did not write",
            "(first: a.txt)",
        ],
    );
    assert_eq!(tree(t.path()), before);
}

#[test]
fn the_current_directory_and_what_holds_it_are_refused() {
    let t = tempfile::tempdir().unwrap();
    let project = t.path().join("project");
    put(
        &project,
        &[
            (".git/HEAD", "ref: refs/heads/main\n"),
            ("src/main.rs", "fn main() {}\n"),
        ],
    );
    let before = tree(t.path());
    let here = project.to_str().unwrap();
    for (out, why) in [
        (here, "it is the current directory"),
        (".", "it is the current directory"),
        ("src/..", "it is the current directory"),
        ("..", "it holds the current directory"),
    ] {
        let o = run(&project, &["generate", "--no-traces", "--out", out]);
        assert_refused(&o, 2, &[&format!("refusing to write into {out}"), why]);
        assert_eq!(tree(t.path()), before, "--out {out}");
    }
    let o = run(&project, &["generate", "--no-traces", "--out", "nope/.."]);
    assert_refused(&o, 2, &["`..` after a directory that does not exist"]);
    assert_eq!(tree(t.path()), before);
}

#[test]
fn home_and_root_are_refused() {
    let t = tempfile::tempdir().unwrap();
    let home = t.path().join("home");
    let work = t.path().join("work");
    put(&home, &[(".bashrc", "# mine\n")]);
    fs::create_dir(&work).unwrap();
    let before = tree(t.path());
    for (out, why) in [
        (home.to_str().unwrap(), "it is your home directory"),
        ("/", "it is the root directory"),
    ] {
        let mut c = fs_state::command(&work, &["generate", "--no-traces", "--out", out]);
        c.env("HOME", &home);
        let o = fs_state::finish(c);
        assert_refused(&o, 2, &[why]);
        assert_eq!(tree(t.path()), before, "--out {out}");
    }
    let staged = names(std::path::Path::new("/"))
        .into_iter()
        .filter(|n| n.starts_with(".motionhdl"))
        .count();
    assert_eq!(staged, 0, "a staging name was left in /");
}

#[test]
fn a_repository_root_and_the_config_files_directory_are_refused() {
    let t = tempfile::tempdir().unwrap();
    put(
        t.path(),
        &[("repo/.git/HEAD", "x\n"), ("conf/c.toml", "axes = 2\n")],
    );
    let before = tree(t.path());
    let o = run(t.path(), &["generate", "--no-traces", "--out", "repo"]);
    assert_refused(&o, 2, &["it is the root of a repository (it has .git)"]);
    // --force keeps foreign files, but these two are refused even so.
    let o = run(
        t.path(),
        &["generate", "--no-traces", "--out", "repo", "--force"],
    );
    assert_refused(&o, 2, &["repository"]);
    let o = run(
        t.path(),
        &[
            "generate",
            "--out",
            "conf",
            "--config",
            "conf/c.toml",
            "--force",
        ],
    );
    assert_refused(&o, 2, &["it holds the configuration file", "c.toml"]);
    assert_eq!(tree(t.path()), before);
}

#[test]
fn an_existing_file_as_the_output_directory_is_refused_untouched() {
    let t = tempfile::tempdir().unwrap();
    put(t.path(), &[("notes", "my notes\n")]);
    let before = tree(t.path());
    let o = run(t.path(), &["generate", "--no-traces", "--out", "notes"]);
    assert_refused(
        &o,
        2,
        &["cannot write into notes: it is a file, not a directory"],
    );
    assert_eq!(tree(t.path()), before);
}

/// The whole output (traces too), replaced by another configuration's
/// output without traces, then by the whole one again: each time exactly
/// what that run writes, so `vcd/` goes and comes back whole.
#[test]
fn generate_replaces_its_own_output_exactly_and_leaves_nothing_beside_it() {
    let t = tempfile::tempdir().unwrap();
    let cfg = t.path().join("two.toml");
    fs::write(&cfg, "axes = 2\n").unwrap();
    let o = run(t.path(), &["generate", "--out", "gen"]);
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    assert_eq!(tree(&t.path().join("gen")), expected_output(""));
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
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    let quick = expected_quick_output("axes = 2\n");
    assert!(!quick.keys().any(|p| p.starts_with("vcd")), "no trace");
    assert_eq!(tree(&t.path().join("gen")), quick);
    let o = run(t.path(), &["generate", "--out", "gen"]);
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    assert_eq!(tree(&t.path().join("gen")), expected_output(""));
    assert_eq!(names(t.path()), ["gen", "two.toml"]);
}

#[test]
fn an_edited_output_file_is_refused_without_force_and_replaced_with_it() {
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["generate", "--no-traces", "--out", "gen"])
        .status
        .success());
    let edited = t.path().join("gen/verilog/ls153.v");
    fs::write(&edited, "// my fix\n").unwrap();
    let before = tree(t.path());
    let o = run(t.path(), &["generate", "--no-traces", "--out", "gen"]);
    assert_refused(
        &o,
        2,
        &["verilog/ls153.v was changed since motionhdl wrote it"],
    );
    assert_eq!(tree(t.path()), before);
    let o = run(
        t.path(),
        &["generate", "--no-traces", "--out", "gen", "--force"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    assert_eq!(tree(&t.path().join("gen")), expected_quick_output(""));
}

#[test]
fn force_keeps_every_foreign_file_as_the_same_file() {
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["generate", "--no-traces", "--out", "gen"])
        .status
        .success());
    let gen = t.path().join("gen");
    put(
        &gen,
        &[
            ("notes.txt", "mine"),
            ("verilog/my_top.v", "module my_top; endmodule\n"),
        ],
    );
    fs::create_dir(gen.join("empty")).unwrap();
    std::os::unix::fs::symlink("verilog/my_top.v", gen.join("top.v")).unwrap();
    let inodes = (
        inode(&gen.join("notes.txt")),
        inode(&gen.join("verilog/my_top.v")),
    );
    let o = run(
        t.path(),
        &["generate", "--no-traces", "--out", "gen", "--force"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    assert!(fs_state::stderr(&o).is_empty());
    assert!(String::from_utf8_lossy(&o.stdout).contains("kept 4 file(s) motionhdl did not write"));
    let mut want = expected_quick_output("");
    want.insert("notes.txt".into(), Node::File(b"mine".to_vec()));
    want.insert(
        "verilog/my_top.v".into(),
        Node::File(b"module my_top; endmodule\n".to_vec()),
    );
    want.insert("empty".into(), Node::Dir);
    want.insert("top.v".into(), Node::Link("verilog/my_top.v".into()));
    assert_eq!(tree(&gen), want);
    assert_eq!(
        inodes,
        (
            inode(&gen.join("notes.txt")),
            inode(&gen.join("verilog/my_top.v"))
        )
    );
    assert_eq!(names(t.path()), ["gen"]);
}

#[test]
fn force_never_replaces_a_foreign_file_standing_where_it_writes() {
    let t = tempfile::tempdir().unwrap();
    put(
        t.path(),
        &[
            ("gen/REGISTERS.md", "# my register notes\n"),
            ("gen/keep.txt", "k"),
        ],
    );
    let before = tree(t.path());
    let o = run(
        t.path(),
        &["generate", "--no-traces", "--out", "gen", "--force"],
    );
    assert_refused(&o, 2, &["REGISTERS.md: the file there is not motionhdl's"]);
    assert_eq!(tree(t.path()), before);
    // A foreign file where a directory of the output goes.
    fs::remove_file(t.path().join("gen/REGISTERS.md")).unwrap();
    put(t.path(), &[("gen/verilog", "not a directory")]);
    let before = tree(t.path());
    let o = run(
        t.path(),
        &["generate", "--no-traces", "--out", "gen", "--force"],
    );
    assert_refused(&o, 2, &["gen/verilog: the file there is not motionhdl's"]);
    assert_eq!(tree(t.path()), before);
}

#[test]
fn output_from_before_the_manifest_is_recognised_by_its_banner() {
    let t = tempfile::tempdir().unwrap();
    assert!(run(t.path(), &["generate", "--no-traces", "--out", "gen"])
        .status
        .success());
    let gen = t.path().join("gen");
    fs::remove_file(gen.join("MANIFEST.sha256")).unwrap();
    // A file an older version wrote and this one does not.
    put(
        &gen,
        &[(
            "verilog/old_block.v",
            "// Generated by motionhdl 0.0.9 — do not edit\n",
        )],
    );
    let o = run(t.path(), &["generate", "--no-traces", "--out", "gen"]);
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    assert_eq!(tree(&gen), expected_quick_output(""));
    // Without the banner the same file is the user's.
    fs::remove_file(gen.join("MANIFEST.sha256")).unwrap();
    put(&gen, &[("verilog/old_block.v", "// my block\n")]);
    let o = run(t.path(), &["generate", "--no-traces", "--out", "gen"]);
    assert_refused(&o, 2, &["(first: verilog/old_block.v)"]);
}

#[test]
fn an_empty_directory_is_filled_keeping_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let t = tempfile::tempdir().unwrap();
    let gen = t.path().join("gen");
    fs::create_dir(&gen).unwrap();
    fs::set_permissions(&gen, fs::Permissions::from_mode(0o750)).unwrap();
    assert!(run(t.path(), &["generate", "--no-traces", "--out", "gen"])
        .status
        .success());
    assert_eq!(tree(&gen), expected_quick_output(""));
    assert_eq!(
        fs::metadata(&gen).unwrap().permissions().mode() & 0o777,
        0o750
    );
}

#[test]
fn a_name_of_250_characters_works_for_generate_and_trace() {
    let t = tempfile::tempdir().unwrap();
    let long = "g".repeat(250);
    let o = run(t.path(), &["generate", "--no-traces", "--out", &long]);
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    assert_eq!(tree(&t.path().join(&long)), expected_quick_output(""));
    let vcd = format!("{}.vcd", "t".repeat(246));
    let o = run(t.path(), &["trace", "pulse_mode_selector", "--out", &vcd]);
    assert_eq!(o.status.code(), Some(0), "{}", fs_state::stderr(&o));
    let gtkw = format!("{}.gtkw", "t".repeat(246));
    let mut want = vec![long, vcd, gtkw];
    want.sort();
    assert_eq!(names(t.path()), want);
}

#[test]
fn trace_refuses_a_save_file_name_and_a_directory() {
    let t = tempfile::tempdir().unwrap();
    put(t.path(), &[("x.gtkw", "[*] my view\n"), ("d/keep", "k")]);
    let before = tree(t.path());
    let o = run(
        t.path(),
        &["trace", "pulse_mode_selector", "--out", "x.gtkw"],
    );
    assert_refused(&o, 2, &["x.gtkw would be written twice", "ending in .vcd"]);
    let o = run(t.path(), &["trace", "pulse_mode_selector", "--out", "d"]);
    assert_refused(&o, 2, &["cannot write d: it is a directory"]);
    assert_eq!(tree(t.path()), before);
}

#[test]
fn trace_replaces_only_files_motionhdl_wrote_unless_forced() {
    let t = tempfile::tempdir().unwrap();
    let args = ["trace", "pulse_mode_selector", "--out", "sel.vcd"];
    assert!(run(t.path(), &args).status.success());
    let first = tree(t.path());
    assert!(
        run(t.path(), &args).status.success(),
        "its own trace is replaced"
    );
    assert_eq!(tree(t.path()), first);
    // GTKWave rewrites a save file without motionhdl's banner: the user's view.
    put(
        t.path(),
        &[(
            "sel.gtkw",
            "[*] GTKWave Analyzer v3.3.118\n[timestart] 100\n",
        )],
    );
    let before = tree(t.path());
    let o = run(t.path(), &args);
    assert_refused(
        &o,
        2,
        &["refusing to overwrite sel.gtkw: motionhdl did not write it"],
    );
    assert_eq!(tree(t.path()), before);
    let mut forced = args.to_vec();
    forced.push("--force");
    assert!(run(t.path(), &forced).status.success());
    assert_eq!(tree(t.path()), first);
}
