//! `motionhdl verify`: every exhaustive check, as a table.

use motionhdl_testbench::CheckReport;

/// Runs the checks of the testbench's registry (see
/// `motionhdl_testbench::registry`): all, or the groups in `only`, which
/// must be known.
pub fn run(external: bool, only: &[String]) -> Result<Vec<CheckReport>, crate::CliError> {
    use motionhdl_testbench::registry;
    let names = registry::group_names();
    if let Some(bad) = only.iter().find(|o| !names.contains(&o.as_str())) {
        return Err(crate::CliError::input(format!(
            "--only {bad} is not a group of checks: use one of {}",
            names.join(", ")
        )));
    }
    // Group by group, so a long run shows which one it is in.
    let mut reports = Vec::new();
    for name in registry::selected(only) {
        let stage = crate::progress::Stage::start(format!("verify {name}"));
        reports.extend(registry::run_group(external, name));
        stage.finish();
    }
    Ok(reports)
}

/// The table `motionhdl verify` prints.
pub fn table(reports: &[CheckReport]) -> String {
    let headers = ["block", "check", "covered", "expected", "result"];
    let rows: Vec<[String; 5]> = reports
        .iter()
        .map(|r| {
            [
                r.block.clone(),
                r.check.clone(),
                r.covered.to_string(),
                r.expected.to_string(),
                r.result(),
            ]
        })
        .collect();
    let mut widths = headers.map(|h| h.chars().count());
    for row in &rows {
        for (w, c) in widths.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: [&str; 5]| -> String {
        let mut s = String::new();
        for (i, (c, w)) in cells.iter().zip(widths).enumerate() {
            let pad = w - c.chars().count();
            if i == 2 || i == 3 {
                s.push_str(&" ".repeat(pad));
                s.push_str(c);
            } else {
                s.push_str(c);
                s.push_str(&" ".repeat(pad));
            }
            s.push_str("  ");
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(headers);
    out.push_str(&line(
        widths.map(|w| "-".repeat(w)).each_ref().map(|s| s.as_str()),
    ));
    for row in &rows {
        out.push_str(&line(row.each_ref().map(|s| s.as_str())));
    }
    out
}
