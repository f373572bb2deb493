//! Running the external tools (yosys, nextpnr) the way `synth` does: the
//! command line shown, a progress stage while it runs, its output into
//! files of a scratch directory, a caught signal stopping it, and the
//! tool's version for the report.

use crate::CliError;
use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};

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

/// The first line of `program --version` (`-V` for yosys), to say which
/// tool produced a figure.
pub fn version(program: &Path) -> String {
    let is_yosys = program
        .file_name()
        .is_some_and(|n| n.to_string_lossy().contains("yosys"));
    let flag = if is_yosys { "-V" } else { "--version" };
    match Command::new(program)
        .arg(flag)
        .stdin(Stdio::null())
        .output()
    {
        Ok(o) => {
            let text = String::from_utf8_lossy(&o.stdout).to_string()
                + &String::from_utf8_lossy(&o.stderr);
            text.lines()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("(no version printed)")
                .trim()
                .to_string()
        }
        Err(e) => format!("(cannot run {} {flag}: {e})", program.display()),
    }
}

/// Runs one tool in `dir` to completion, its output into files there. A
/// caught signal (see [`crate::interrupt`]) stops the tool and the run.
pub fn run(cmd: &mut Command, what: &str, dir: &Path, log: &str) -> Result<(), CliError> {
    let cannot = |e: std::io::Error| CliError::failure(format!("cannot run {what}: {e}"));
    let stderr_path = dir.join(format!("{what}.stderr"));
    eprintln!("$ {}", command_line(cmd));
    let stage = crate::progress::Stage::start(what);
    let mut child = cmd
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::from(
            File::create(dir.join(format!("{what}.stdout"))).map_err(cannot)?,
        ))
        .stderr(Stdio::from(File::create(&stderr_path).map_err(cannot)?))
        .spawn()
        .map_err(cannot)?;
    let status = loop {
        if let Some(sig) = crate::interrupt::pending() {
            let _ = child.kill();
            let _ = child.wait();
            return Err(crate::interrupt::interrupted(
                sig,
                &format!("{what} stopped, its scratch directory removed"),
            ));
        }
        match child.try_wait().map_err(cannot)? {
            Some(status) => break status,
            None => std::thread::sleep(std::time::Duration::from_millis(20)),
        }
    };
    stage.finish();
    if !status.success() {
        let text = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
        let tail: Vec<&str> = text.lines().rev().take(25).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(CliError::failure(format!(
            "{what} failed ({status}):\n{}\n{}",
            std::fs::read_to_string(&stderr_path)
                .unwrap_or_default()
                .trim(),
            tail.join("\n")
        )));
    }
    Ok(())
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
