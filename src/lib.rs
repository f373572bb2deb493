//! The `motionhdl` tool: configuration, the generated artifacts, and the
//! commands behind the CLI.

pub mod artifacts;
pub mod board;
pub mod c_writer;
pub mod config_file;
pub mod constraints;
pub mod formal;
pub mod fusesoc;
pub mod interrupt;
pub mod isa_header;
pub mod output;
pub mod progress;
pub mod regmap_export;
pub mod sweep;
pub mod synth;
pub mod text;
pub mod tool;
pub mod verify;

/// An error the CLI reports; `exit_code` 2 means bad input (nothing written).
#[derive(Debug)]
pub struct CliError {
    pub message: String,
    pub exit_code: i32,
}

impl CliError {
    /// Bad input from the user: exit code 2.
    pub fn input(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            exit_code: 2,
        }
    }
    /// A failure while doing the work: exit code 1.
    pub fn failure(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            exit_code: 1,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}
