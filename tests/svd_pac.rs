//! The generated SVD through svd2rust, as a firmware engineer uses it: the
//! peripheral access crate builds for `thumbv7em-none-eabihf` with
//! `-D warnings`, the counter channels and the pulse axes are arrays
//! (`ch(n)`, `ax(n)`), and a crate that forbids `unsafe` writes ranged
//! fields with `set`. Without the SVD's `writeConstraint`s the same crate
//! does not build: the test can fail.
//!
//! The PAC's own dependencies (`vcell`, `critical-section`) are dev-
//! dependencies of this package, so cargo has them and builds `--offline`.

mod common;

use common::run;
use motionhdl_testbench::harness::{require_rust_target, require_tool};
use std::path::Path;
use std::process::Command;

const TARGET: &str = "thumbv7em-none-eabihf";

/// Firmware as a user writes it: no `unsafe`, ranged fields by `set`,
/// the clusters by index and by iterator.
const USER: &str = r#"#![no_std]
#![forbid(unsafe_code)]
use motionhdl_pac as pac;

pub fn configure(counter: &pac::Counter, pulse: &pac::Pulse) {
    counter.ch(2).ctrl().write(|w| w.filter_ab().set(3));
    for ch in counter.ch_iter() {
        ch.ctrl().modify(|_, w| w.filter_ab().set(1));
    }
    pulse.ax(1).step_timing().write(|w| w.step_len().set(2).step_space().set(2));
}
"#;

fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
}

/// Writes `svd`'s PAC and the user crate under `dir`; runs cargo build
/// for the target: (built, cargo's output, the PAC's source).
fn build_pac(dir: &Path, svd: &str) -> (bool, String, String) {
    let svd_file = dir.join("motionhdl.svd");
    std::fs::write(&svd_file, svd).unwrap();
    let pac = dir.join("pac");
    std::fs::create_dir_all(pac.join("src")).unwrap();
    let (ok, out, err) = run(Command::new("svd2rust")
        .args(["--target", "none", "-i"])
        .arg(&svd_file)
        .arg("-o")
        .arg(pac.join("src")));
    assert!(ok, "svd2rust:\n{out}{err}");
    std::fs::write(
        pac.join("Cargo.toml"),
        "[package]\nname = \"motionhdl-pac\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\n\
         [dependencies]\nvcell = \"0.1.3\"\ncritical-section = { version = \"1.1\", optional = true }\n\n\
         [features]\nrt = []\n\n[workspace]\n",
    )
    .unwrap();
    let user = dir.join("user");
    std::fs::create_dir_all(user.join("src")).unwrap();
    std::fs::write(
        user.join("Cargo.toml"),
        "[package]\nname = \"user\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\n\
         [dependencies]\nmotionhdl-pac = { path = \"../pac\", features = [\"critical-section\"] }\n\n\
         [workspace]\n",
    )
    .unwrap();
    std::fs::write(user.join("src/lib.rs"), USER).unwrap();
    let (ok, out, err) = run(Command::new(cargo())
        .current_dir(&user)
        .args(["build", "--offline", "--release", "--target", TARGET])
        .env("RUSTFLAGS", "-D warnings")
        .env("CARGO_TARGET_DIR", dir.join("target")));
    let source = std::fs::read_to_string(pac.join("src/lib.rs")).unwrap();
    (ok, format!("{out}{err}"), source)
}

#[test]
fn svd2rust_pac_builds_for_cortex_m_and_needs_no_unsafe_for_ranged_writes() {
    if require_tool("svd2rust").is_none() {
        return;
    }
    if require_rust_target(TARGET).is_none() {
        return;
    }
    let svd = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/motionhdl.svd"),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (ok, log, source) = build_pac(dir.path(), &svd);
    assert!(ok, "the PAC and its user do not build:\n{log}");
    for array in [
        "pub const fn ch (& self , n : usize) -> & Ch",
        "pub const fn ax (& self , n : usize) -> & Ax",
    ] {
        assert!(source.contains(array), "no cluster array `{array}`");
    }
    // The same SVD without its write constraints: svd2rust cannot know a
    // value is in range, every field write needs `unsafe`, and the user
    // crate (which forbids it) no longer builds.
    let constraints = svd.matches("<writeConstraint>").count();
    assert!(constraints > 50, "{constraints} write constraints");
    let mut stripped = String::new();
    let mut rest = svd.as_str();
    while let Some(start) = rest.find("<writeConstraint>") {
        let end = rest[start..].find("</writeConstraint>").unwrap() + start;
        stripped.push_str(&rest[..start]);
        rest = &rest[end + "</writeConstraint>".len()..];
    }
    stripped.push_str(rest);
    let broken = tempfile::tempdir().unwrap();
    let (ok, log, _) = build_pac(broken.path(), &stripped);
    assert!(!ok, "built without write constraints:\n{log}");
    assert!(
        log.contains("E0599") || log.contains("E0133"),
        "failed for another reason:\n{log}"
    );
    println!("PAC built; {constraints} write constraints; without them the user crate fails");
}
