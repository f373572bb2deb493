//! Ctrl-C, SIGTERM and SIGHUP while files are being replaced or tools run.
//!
//! Once [`catch`] is called a signal only sets a flag; the work looks at it at
//! its checkpoints, where nothing is half-done, and unwinds from there, so
//! every staging file and scratch directory is removed by its owner. Before
//! `catch` (while outputs are computed in memory) a signal ends the process
//! as usual, which is safe because nothing has been written yet.
//!
//! Tests drive interruptions deterministically through the environment
//! variable `MOTIONHDL_TEST_HOOK`: a comma-separated list of `STEP=ACTION`,
//! where ACTION is `sigint` or `sigterm` (the process sends itself that
//! signal at STEP) or `sigkill` (it dies there, as after a power cut, leaving
//! whatever is on disk for the next run to recognise).

use crate::CliError;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

static CAUGHT: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

/// From now on SIGINT, SIGTERM and SIGHUP set a flag instead of ending the
/// process. Idempotent.
pub fn catch() {
    CAUGHT.get_or_init(|| {
        let flag = Arc::new(AtomicUsize::new(0));
        for sig in [
            signal_hook::consts::SIGINT,
            signal_hook::consts::SIGTERM,
            signal_hook::consts::SIGHUP,
        ] {
            signal_hook::flag::register_usize(sig, Arc::clone(&flag), sig as usize)
                .expect("install a signal handler");
        }
        flag
    });
}

/// The signal that arrived since [`catch`], if any.
pub fn pending() -> Option<i32> {
    CAUGHT
        .get()
        .map(|f| f.load(Ordering::SeqCst))
        .filter(|&s| s != 0)
        .map(|s| s as i32)
}

/// The name of a signal we catch.
pub fn signal_name(sig: i32) -> &'static str {
    match sig {
        signal_hook::consts::SIGINT => "SIGINT",
        signal_hook::consts::SIGTERM => "SIGTERM",
        signal_hook::consts::SIGHUP => "SIGHUP",
        _ => "a signal",
    }
}

/// The error a run ends with after `sig`: exit code 128 + signal, as a shell
/// reports a process killed by it. `state` says what is on disk.
pub fn interrupted(sig: i32, state: &str) -> CliError {
    CliError {
        message: format!("interrupted by {}: {state}", signal_name(sig)),
        exit_code: 128 + sig,
    }
}

/// Runs the test hook for `step` (see the module doc) and reports a signal
/// that has arrived: `Err(signal)` means stop here.
pub fn checkpoint(step: &str) -> Result<(), i32> {
    hook(step);
    pending().map_or(Ok(()), Err)
}

/// Runs the test hook for `step` without stopping: for steps after the point
/// of no return, where the work is finished whatever arrives.
pub fn hook(step: &str) {
    let Some(spec) = std::env::var_os("MOTIONHDL_TEST_HOOK") else {
        return;
    };
    let spec = spec.to_string_lossy();
    for item in spec.split(',') {
        let Some((at, action)) = item.split_once('=') else {
            continue;
        };
        if at.trim() != step {
            continue;
        }
        let sig = match action.trim() {
            "sigint" => signal_hook::consts::SIGINT,
            "sigterm" => signal_hook::consts::SIGTERM,
            "sigkill" => signal_hook::consts::SIGKILL,
            other => panic!("MOTIONHDL_TEST_HOOK: unknown action `{other}` at `{step}`"),
        };
        signal_hook::low_level::raise(sig).expect("raise a signal");
    }
}
