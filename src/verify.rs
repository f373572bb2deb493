//! `motionhdl verify`: every exhaustive check, as a table.

use motionhdl_testbench::CheckReport;

/// What `verify` ran: the exhaustive checks and the formal proofs.
pub struct Verified {
    pub checks: Vec<CheckReport>,
    pub proofs: Vec<crate::formal::ProofReport>,
    /// Why the proofs did not run, when they were selected but their
    /// tools are missing (outside CI; under CI that is an error).
    pub proofs_skipped: Option<String>,
}

/// The group of `--only` that selects the formal proofs.
pub const FORMAL: &str = "formal";

/// Runs the checks of the testbench's registry (see
/// `motionhdl_testbench::registry`) and then the formal proofs (see
/// [`crate::formal`]; with `long`, the long ones too): all, or the groups
/// in `only`, which must be known. The proofs need the external tools.
pub fn run(external: bool, only: &[String], long: bool) -> Result<Verified, crate::CliError> {
    use motionhdl_testbench::registry;
    let mut names = registry::group_names();
    names.push(FORMAL);
    if let Some(bad) = only.iter().find(|o| !names.contains(&o.as_str())) {
        return Err(crate::CliError::input(format!(
            "--only {bad} is not a group of checks: use one of {}",
            names.join(", ")
        )));
    }
    let formal = only.is_empty() || only.iter().any(|o| o == FORMAL);
    if formal && !external && !only.is_empty() {
        return Err(crate::CliError::input(
            "--only formal runs SymbiYosys, an external tool: drop --no-external",
        ));
    }
    // Group by group, so a long run shows which one it is in.
    let mut checks = Vec::new();
    for name in registry::selected(only) {
        let stage = crate::progress::Stage::start(format!("verify {name}"));
        checks.extend(registry::run_group(external, name));
        stage.finish();
    }
    let mut verified = Verified {
        checks,
        proofs: Vec::new(),
        proofs_skipped: None,
    };
    if formal && external {
        match crate::formal::sby::find_tools() {
            Ok(_) => verified.proofs = crate::formal::run(long)?,
            Err(e) if std::env::var_os("CI").is_none() => verified.proofs_skipped = Some(e.message),
            Err(e) => return Err(e),
        }
    }
    Ok(verified)
}

/// The table `motionhdl verify` prints.
pub fn table(reports: &[CheckReport]) -> String {
    let rows: Vec<Vec<String>> = reports
        .iter()
        .map(|r| {
            vec![
                r.block.clone(),
                r.check.clone(),
                r.covered.to_string(),
                r.expected.to_string(),
                r.result(),
            ]
        })
        .collect();
    crate::text::columns(
        &["block", "check", "covered", "expected", "result"],
        &rows,
        &[2, 3],
    )
}
