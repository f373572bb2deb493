//! Helpers shared by the integration tests: running a tool and reading C
//! headers back. `regmap` holds the register-map tests' table and the
//! read-backs more than one of their files runs; `isa` the numbers the ISA
//! header must define; `fs_state` runs the `motionhdl` binary and takes
//! exact pictures of the trees it leaves.

// Every test crate compiles this module but uses only part of it.
#![allow(dead_code)]

pub mod fs_state;
pub mod isa;
pub mod regmap;

use motionhdl::artifacts::{self, Artifact, Traces};
use std::collections::HashMap;
use std::process::Command;
use std::sync::{Mutex, OnceLock};

/// `artifacts::all` for the configuration file text `config_text`,
/// computed once per test binary (see [`on_disk`]): `generate`'s whole
/// output takes seconds (the whole-controller traces), and the tests only
/// read it.
pub fn artifacts_for(config_text: &str) -> &'static [Artifact] {
    cached(config_text, Traces::Write)
}

/// `artifacts::without_traces` for `config_text`, once per test binary.
pub fn artifacts_without_traces(config_text: &str) -> &'static [Artifact] {
    cached(config_text, Traces::Leave)
}

fn cached(config_text: &str, traces: Traces) -> &'static [Artifact] {
    type Done = HashMap<(String, Traces), &'static [Artifact]>;
    static DONE: OnceLock<Mutex<Done>> = OnceLock::new();
    let mut done = DONE.get_or_init(Default::default).lock().unwrap();
    done.entry((config_text.to_string(), traces))
        .or_insert_with(|| Box::leak(on_disk(config_text, traces).into_boxed_slice()))
}

/// The artifacts from a copy on disk that every test process of this
/// test binary shares: nextest runs each test in its own process, and
/// the whole-controller traces take some 25 s to simulate. The copy is
/// keyed by the binary (its size and time) and the request, written once
/// under a lock, and read by the later processes.
fn on_disk(config_text: &str, traces: Traces) -> Vec<Artifact> {
    use std::hash::{Hash, Hasher};
    let exe = std::fs::metadata(std::env::current_exe().unwrap()).unwrap();
    let mut key = std::collections::hash_map::DefaultHasher::new();
    (exe.len(), exe.modified().ok(), config_text, traces).hash(&mut key);
    let root = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("artifacts");
    std::fs::create_dir_all(&root).unwrap();
    let dir = root.join(format!("{:016x}", key.finish()));
    let lock = std::fs::File::create(root.join(".lock")).unwrap();
    lock.lock().unwrap();
    if !dir.join(".complete").is_file() {
        let config = motionhdl::config_file::parse(config_text, "test").unwrap();
        let fresh = artifacts::with_traces(&config, traces);
        let _ = std::fs::remove_dir_all(&dir);
        for a in &fresh {
            let f = dir.join(&a.path);
            std::fs::create_dir_all(f.parent().unwrap()).unwrap();
            std::fs::write(f, &a.contents).unwrap();
        }
        let list: Vec<String> = fresh.iter().map(|a| a.path.display().to_string()).collect();
        std::fs::write(dir.join(".complete"), list.join("\n")).unwrap();
        return fresh;
    }
    // In `generate`'s order, which `.complete` lists.
    let list = std::fs::read_to_string(dir.join(".complete")).unwrap();
    list.lines()
        .map(|p| Artifact {
            path: p.into(),
            contents: std::fs::read(dir.join(p)).unwrap(),
        })
        .collect()
}

/// Runs `cmd` to completion: (exit status was success, stdout, stderr).
pub fn run(cmd: &mut Command) -> (bool, String, String) {
    let o = cmd.output().expect("start tool");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).to_string(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

/// A C integer literal: decimal or 0x hex, with optional u/l suffixes.
pub fn c_number(s: &str) -> Option<u64> {
    let t = s.trim_end_matches(['u', 'U', 'l', 'L']);
    match t.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    }
}

/// Every `#define` of a header: (name, or name(params) for function-like
/// macros; the replacement text).
pub fn defines(h: &str) -> Vec<(String, String)> {
    h.lines()
        .filter_map(|l| l.strip_prefix("#define "))
        .map(|rest| {
            // A function-like macro's name runs to its closing parenthesis.
            let end = match rest.find('(') {
                Some(i) if !rest[..i].contains(' ') => rest.find(')').unwrap() + 1,
                _ => rest.find(' ').unwrap_or(rest.len()),
            };
            (rest[..end].to_string(), rest[end..].trim().to_string())
        })
        .collect()
}
