//! Running the `motionhdl` binary and taking exact pictures of a directory
//! tree, so a test can say what a run left behind, byte for byte.

use std::collections::BTreeMap;
use std::fs;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary under test: `MOTIONHDL_BIN` if set (to run these tests
/// against another build, e.g. an older commit), else this crate's.
pub fn bin() -> PathBuf {
    std::env::var_os("MOTIONHDL_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_motionhdl")))
}

/// A `motionhdl` command run in `cwd`, without any test hook inherited.
pub fn command(cwd: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(bin());
    c.args(args)
        .current_dir(cwd)
        .env_remove("MOTIONHDL_TEST_HOOK");
    c
}

pub fn run(cwd: &Path, args: &[&str]) -> Output {
    finish(command(cwd, args))
}

/// Runs `cmd` to its end, killing it after 120 s (a run that hangs, e.g.
/// reading /dev/zero for ever, fails its test instead of stalling the suite;
/// the slowest run here takes a few seconds).
pub fn finish(mut cmd: Command) -> Output {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run motionhdl");
    let pid = child.id();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(child.wait_with_output());
    });
    let start = Instant::now();
    match rx.recv_timeout(Duration::from_secs(120)) {
        Ok(out) => out.expect("wait for motionhdl"),
        Err(_) => {
            // SIGKILL by PID: the waiting thread still owns the child.
            unsafe { libc::kill(pid as libc::pid_t, libc::SIGKILL) };
            panic!("motionhdl did not finish in {:?}: killed", start.elapsed());
        }
    }
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts the exit code and that stderr holds every one of `needles`.
pub fn assert_refused(o: &Output, code: i32, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "exit code; stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr lacks {n:?}: {err}");
    }
}

/// One entry of a tree: a file's bytes and inode, a link's target, or a
/// directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Node {
    File(Vec<u8>),
    Link(PathBuf),
    Dir,
}

/// Every entry below `root` (relative path → node), not following links.
pub fn tree(root: &Path) -> BTreeMap<String, Node> {
    let mut out = BTreeMap::new();
    let mut stack = vec![(root.to_path_buf(), String::new())];
    while let Some((dir, rel)) = stack.pop() {
        for e in fs::read_dir(&dir).unwrap() {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            let rel = if rel.is_empty() {
                name
            } else {
                format!("{rel}/{name}")
            };
            let t = e.file_type().unwrap();
            let node = if t.is_dir() {
                stack.push((e.path(), rel.clone()));
                Node::Dir
            } else if t.is_symlink() {
                Node::Link(fs::read_link(e.path()).unwrap())
            } else {
                Node::File(fs::read(e.path()).unwrap())
            };
            out.insert(rel, node);
        }
    }
    out
}

/// The names directly in `dir`, sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

pub fn inode(path: &Path) -> u64 {
    fs::symlink_metadata(path).unwrap().ino()
}

/// The tree `motionhdl generate` writes for a configuration file's text
/// (`""` for the default), computed in this process.
pub fn expected_output(config_text: &str) -> BTreeMap<String, Node> {
    tree_of(super::artifacts_for(config_text))
}

/// The tree `generate --no-traces` leaves for `config_text`: every file
/// but `vcd/`, and the manifest listing them.
pub fn expected_quick_output(config_text: &str) -> BTreeMap<String, Node> {
    tree_of(super::artifacts_without_traces(config_text))
}

/// The tree `generate` writes for `artifacts`, manifest included.
fn tree_of(artifacts: &[motionhdl::artifacts::Artifact]) -> BTreeMap<String, Node> {
    let files: Vec<(PathBuf, Vec<u8>)> = artifacts
        .iter()
        .map(|a| (a.path.clone(), a.contents.clone()))
        .collect();
    let mut out = BTreeMap::new();
    for (path, data) in motionhdl::output::manifest::with_manifest(&files) {
        let rel = motionhdl::output::manifest::slash_path(&path);
        let parts: Vec<&str> = rel.split('/').collect();
        for n in 1..parts.len() {
            out.insert(parts[..n].join("/"), Node::Dir);
        }
        out.insert(rel, Node::File(data));
    }
    out
}

/// Writes `files` (relative path → text) below `root`.
pub fn put(root: &Path, files: &[(&str, &str)]) {
    for (rel, text) in files {
        let p = root.join(rel);
        fs::create_dir_all(p.parent().unwrap()).unwrap();
        fs::write(p, text).unwrap();
    }
}
