//! Running the external tools (yosys, nextpnr) the way `synth` does: the
//! command line shown, a progress stage while it runs, its output into
//! files of a scratch directory, a caught signal stopping it, and the
//! tool's version for the report.

use crate::CliError;
use std::fs::File;
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// A command as a shell would take it: the program and its arguments,
/// quoted where they hold spaces or quotes.
pub fn command_line(cmd: &Command) -> String {
    let quote = |a: &std::ffi::OsStr| {
        let a = a.to_string_lossy();
        if a.is_empty() || a.contains([' ', '"', '\'', ';', '$']) {
            format!("'{}'", a.replace('\'', "'\\''"))
        } else {
            a.into_owned()
        }
    };
    std::iter::once(quote(cmd.get_program()))
        .chain(cmd.get_args().map(quote))
        .collect::<Vec<_>>()
        .join(" ")
}

/// How long a tool may take to print its version.
const VERSION_LIMIT: Duration = Duration::from_secs(10);

/// The first line of `program --version` (`-V` for yosys), to say which
/// tool produced a figure. A caught signal stops the tool and is the error
/// (signals are caught from here on); a tool that says nothing within
/// [`VERSION_LIMIT`] is stopped and reported as such.
pub fn version(program: &Path, what: &str) -> Result<String, CliError> {
    crate::interrupt::catch();
    let is_yosys = program
        .file_name()
        .is_some_and(|n| n.to_string_lossy().contains("yosys"));
    let flag = if is_yosys { "-V" } else { "--version" };
    let cannot = |e: std::io::Error| format!("(cannot run {} {flag}: {e})", program.display());
    let mut child = match Command::new(program)
        .arg(flag)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => return Ok(cannot(e)),
    };
    let Some(_) = wait(&mut child, &format!("{what} stopped"), Some(VERSION_LIMIT))? else {
        return Ok(format!("(no version within {} s)", VERSION_LIMIT.as_secs()));
    };
    // A version is a few lines: the pipes hold them until now.
    let mut text = String::new();
    if let Some(mut out) = child.stdout.take() {
        let _ = out.read_to_string(&mut text);
    }
    if let Some(mut err) = child.stderr.take() {
        let _ = err.read_to_string(&mut text);
    }
    Ok(text
        .lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("(no version printed)")
        .trim()
        .to_string())
}

/// Waits for `child`, looking for a caught signal every 20 ms: a signal
/// kills it and is the error (`state` says what that left); so does
/// nothing. Past `limit` the child is killed and `None` returned.
fn wait(
    child: &mut Child,
    state: &str,
    limit: Option<Duration>,
) -> Result<Option<ExitStatus>, CliError> {
    let started = Instant::now();
    loop {
        if let Some(sig) = crate::interrupt::pending() {
            let _ = child.kill();
            let _ = child.wait();
            return Err(crate::interrupt::interrupted(sig, state));
        }
        if let Some(status) = child
            .try_wait()
            .map_err(|e| CliError::failure(format!("cannot wait for a tool: {e}")))?
        {
            return Ok(Some(status));
        }
        if limit.is_some_and(|l| started.elapsed() > l) {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Runs one tool in `dir` to completion, its output into files there. A
/// caught signal (see [`crate::interrupt`]) stops the tool and the run; a
/// failing exit status is an error showing the tool's stderr and the end
/// of `log`.
pub fn run(cmd: &mut Command, what: &str, dir: &Path, log: &str) -> Result<(), CliError> {
    let status = run_status(cmd, what, dir)?;
    if !status.success() {
        let text = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
        let tail: Vec<&str> = text.lines().rev().take(25).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(CliError::failure(format!(
            "{what} failed ({status}):\n{}\n{}",
            std::fs::read_to_string(dir.join(format!("{what}.stderr")))
                .unwrap_or_default()
                .trim(),
            tail.join("\n")
        )));
    }
    Ok(())
}

/// Like [`run`], for a tool whose exit status is a result rather than a
/// failure (SymbiYosys: 0 proved, 2 failed): returns the status.
pub fn run_status(cmd: &mut Command, what: &str, dir: &Path) -> Result<ExitStatus, CliError> {
    let cannot = |e: std::io::Error| CliError::failure(format!("cannot run {what}: {e}"));
    eprintln!("$ {}", command_line(cmd));
    let stage = crate::progress::Stage::start(what);
    let mut child = cmd
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::from(
            File::create(dir.join(format!("{what}.stdout"))).map_err(cannot)?,
        ))
        .stderr(Stdio::from(
            File::create(dir.join(format!("{what}.stderr"))).map_err(cannot)?,
        ))
        .spawn()
        .map_err(cannot)?;
    let status = wait(
        &mut child,
        &format!("{what} stopped, its scratch directory removed"),
        None,
    )?
    .expect("no limit");
    stage.finish();
    Ok(status)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_command_line_reads_as_a_shell_would_take_it() {
        let mut c = Command::new("/usr/bin/yosys");
        c.args([
            "-q",
            "-p",
            "read_verilog a.v; synth_ice40 -top t",
            "it's",
            "",
        ]);
        assert_eq!(
            command_line(&c),
            "/usr/bin/yosys -q -p 'read_verilog a.v; synth_ice40 -top t' 'it'\\''s' ''"
        );
    }
}
