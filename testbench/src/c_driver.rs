//! Building the firmware driver's static library for C programs: the C
//! unit tests and the Cortex-M4 link (`tests/driver_c.rs`), and the C
//! firmware co-simulated with the generated Verilog (`tests/cosim.rs`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The libraries a host program linking the Rust static library needs
/// (`rustc --print native-static-libs`).
pub const HOST_LIBS: [&str; 7] = [
    "-lgcc_s",
    "-lutil",
    "-lrt",
    "-lpthread",
    "-lm",
    "-ldl",
    "-lc",
];

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the testbench sits in the workspace")
        .to_path_buf()
}

/// Builds `libmotionhdl_driver.a` for `target` (or the host) in its own
/// target directory, so it never waits on or disturbs the suite's build;
/// returns the archive.
pub fn driver_lib(target: Option<&str>) -> Result<PathBuf, String> {
    let dir = root().join("target/c-driver");
    let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.current_dir(root())
        .args(["build", "--offline", "--release", "-p", "motionhdl-driver"])
        .env("CARGO_TARGET_DIR", &dir);
    if let Some(t) = target {
        cmd.args(["--target", t]);
    }
    let out = cmd.output().map_err(|e| format!("cargo: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo build of the driver:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let sub = target.map_or(PathBuf::from("release"), |t| Path::new(t).join("release"));
    Ok(dir.join(sub).join("libmotionhdl_driver.a"))
}
