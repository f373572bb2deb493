//! `motionhdl synth --sweep`: every block alone and the board top at
//! several axis counts, on several targets and seeds, as one Markdown table
//! written into the benchmarks document with the commit it measured.
//!
//! A design that does not fit is packed only, so its row says how much
//! logic it needs; an Fmax below the clock is a measurement, not an error.

use crate::synth::{self, Design, Pnr, Report, Target};
use crate::CliError;
use motionhdl_model::Config;
use std::fmt::Write as _;
use std::path::Path;

/// Where the table goes in the document: between these two lines.
pub const BEGIN: &str = "<!-- motionhdl synth --sweep: begin -->";
pub const END: &str = "<!-- motionhdl synth --sweep: end -->";

/// What to measure.
#[derive(Clone, Debug)]
pub struct Plan {
    pub targets: Vec<Target>,
    pub axes: Vec<u32>,
    pub seeds: Vec<u64>,
    /// Every block alone too (at the base configuration's axis count).
    pub blocks: bool,
}

/// How one run ended.
#[derive(Clone, Debug)]
pub enum Outcome {
    Routed(Report),
    /// Placement failed; packing needs `used` of `available` logic cells.
    NoFit {
        used: u64,
        available: u64,
    },
    Failed(String),
}

/// One table row.
#[derive(Clone, Debug)]
pub struct Row {
    pub target: Target,
    pub design: String,
    pub seed: u64,
    pub outcome: Outcome,
}

/// Parses a comma-separated list, each value in `range`, for `--flag`.
pub fn parse_list(
    flag: &str,
    text: &str,
    range: std::ops::RangeInclusive<u64>,
) -> Result<Vec<u64>, CliError> {
    text.split(',')
        .map(|v| {
            v.trim()
                .parse::<u64>()
                .ok()
                .filter(|n| range.contains(n))
                .ok_or_else(|| {
                    CliError::input(format!(
                        "--{flag}: `{v}` is not a number in {}..={} (a comma-separated list)",
                        range.start(),
                        range.end()
                    ))
                })
        })
        .collect()
}

/// The designs of `plan` for `target`, each with its row name.
fn designs(plan: &Plan, base: &Config, target: Target) -> Result<Vec<(String, Design)>, CliError> {
    let mut out = Vec::new();
    if plan.blocks {
        for d in synth::all_blocks(base) {
            out.push((format!("`{}` alone", d.top), d));
        }
    }
    for &n in &plan.axes {
        let config = base
            .with_axes(n.into())
            .map_err(|e| CliError::input(format!("--axes: {e}")))?;
        let name = format!("board top, {n} {}", if n == 1 { "axis" } else { "axes" });
        out.push((name, synth::board_design(&config, target)));
    }
    Ok(out)
}

/// Runs every design of `plan` on every target and seed, reporting each
/// row to `progress` as it completes. yosys runs once a design, nextpnr
/// once a seed (and packs only where the design does not place).
pub fn run(
    plan: &Plan,
    base: &Config,
    progress: &mut dyn FnMut(&Row),
) -> Result<Vec<Row>, CliError> {
    let freq = base.clock_hz() as f64 / 1e6;
    let mut rows = Vec::new();
    for &target in &plan.targets {
        let tools = synth::find_tools(target)?;
        for (name, design) in designs(plan, base, target)? {
            let netlist = synth::synthesize_netlist(&design, target, &tools)?;
            let pnr = |seed, how| {
                synth::place_and_route(&netlist, &design, target, &tools, freq, seed, how)
            };
            for &seed in &plan.seeds {
                let outcome = match pnr(seed, Pnr::Route) {
                    Ok(r) => Outcome::Routed(r),
                    Err(e) if e.exit_code == 1 => no_fit(pnr(seed, Pnr::PackOnly), target, &e),
                    Err(e) => return Err(e),
                };
                let row = Row {
                    target,
                    design: name.clone(),
                    seed,
                    outcome,
                };
                progress(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// A failed place and route: "does not fit" when packing needs more logic
/// than the device has, else the failure itself.
fn no_fit(packed: Result<Report, CliError>, target: Target, failure: &CliError) -> Outcome {
    match packed {
        Ok(p) => match p.utilization.get(logic_key(target)) {
            Some(&(used, available)) if used > available => Outcome::NoFit { used, available },
            _ => Outcome::Failed(first_line(&failure.message)),
        },
        Err(_) => Outcome::Failed(first_line(&failure.message)),
    }
}

fn logic_key(target: Target) -> &'static str {
    match target {
        Target::Ice40Hx8k => "ICESTORM_LC",
        Target::Ecp5_25k => "TRELLIS_COMB",
    }
}

fn first_line(text: &str) -> String {
    text.lines().next().unwrap_or("").replace('|', "/")
}

/// The table header.
pub fn header() -> String {
    "| target | design | seed | logic (LC / COMB) | LUT4 | FFs | carry | RAM blocks | I/O | Fmax MHz (clock) |\n\
     | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n"
        .to_string()
}

/// One table line.
pub fn line(row: &Row) -> String {
    let lead = format!("| {} | {} | {} |", row.target.name(), row.design, row.seed);
    match &row.outcome {
        Outcome::Routed(r) => {
            let avail = r.utilization.get(logic_key(row.target)).map_or(0, |u| u.1);
            let fmax = r.slowest_clock();
            format!(
                "{lead} {} / {avail} | {} | {} | {} | {} | {} | {} |\n",
                r.logic(row.target),
                r.luts(),
                r.ffs(),
                r.carries(),
                r.rams(),
                r.io(),
                fmax.map_or("-".into(), |(a, c)| format!(
                    "{a:.1} ({c:.0}{})",
                    if a < c { ", misses it" } else { "" }
                ))
            )
        }
        Outcome::NoFit { used, available } => format!(
            "{lead} does not fit: {used} / {available} needed at packing ({}) | | | | | | – |\n",
            percent(*used, *available)
        ),
        Outcome::Failed(why) => format!("{lead} failed: {why} | | | | | | – |\n"),
    }
}

fn percent(used: u64, available: u64) -> String {
    (used * 100)
        .checked_div(available)
        .map_or("-".into(), |p| format!("{p} %"))
}

/// The whole section: what was run, on which commit, then the table.
pub fn section(rows: &[Row], command: &str, commit: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{BEGIN}");
    let _ = writeln!(
        s,
        "Measured at commit {commit} by `{command}`; written by that command, do not edit by hand."
    );
    let _ = writeln!(s);
    s.push_str(&header());
    for r in rows {
        s.push_str(&line(r));
    }
    let _ = writeln!(s, "{END}");
    s
}

/// `doc` with its sweep section replaced by `section` (appended, after a
/// heading, when the document has none yet).
pub fn replace_section(doc: &str, section: &str) -> Result<String, String> {
    match (doc.find(BEGIN), doc.find(END)) {
        (Some(b), Some(e)) if b < e => {
            let after = doc[e..].find('\n').map_or(doc.len(), |n| e + n + 1);
            Ok(format!("{}{section}{}", &doc[..b], &doc[after..]))
        }
        (None, None) => Ok(format!(
            "{}\n\n## QoR sweep: `motionhdl synth --sweep`\n\n{section}",
            doc.trim_end_matches('\n')
        )),
        _ => Err(format!(
            "its `{BEGIN}` / `{END}` lines are missing one or out of order"
        )),
    }
}

/// The document at `path`, if a sweep section can go into it (checked
/// before a sweep starts, so that hours of runs are not lost on a typo).
pub fn check_document(path: &Path) -> Result<String, CliError> {
    let doc = std::fs::read_to_string(path)
        .map_err(|e| CliError::input(format!("--write {}: cannot read it: {e}", path.display())))?;
    replace_section(&doc, "")
        .map_err(|why| CliError::input(format!("--write {}: {why}", path.display())))?;
    Ok(doc)
}

/// Writes `section` into the document at `path`: nothing else in it
/// changes, and the file is replaced whole (never half-written).
pub fn write_into(path: &Path, section: &str) -> Result<(), CliError> {
    let new = replace_section(&check_document(path)?, section)
        .map_err(|why| CliError::input(format!("--write {}: {why}", path.display())))?;
    let mode = std::fs::metadata(path).map(|m| m.permissions());
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut tmp = tempfile::NamedTempFile::new_in(dir)
        .map_err(|e| CliError::failure(format!("cannot write into {}: {e}", dir.display())))?;
    std::io::Write::write_all(&mut tmp, new.as_bytes())
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))?;
    if let Ok(mode) = mode {
        let _ = std::fs::set_permissions(tmp.path(), mode);
    }
    tmp.persist(path)
        .map_err(|e| CliError::failure(format!("cannot replace {}: {e}", path.display())))?;
    Ok(())
}

/// The commit measured: `git rev-parse --short HEAD` of the source tree
/// this motionhdl was built from, marked when that tree has changes;
/// "unknown" when it is not a git checkout (any more).
pub fn commit() -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(env!("CARGO_MANIFEST_DIR"))
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(head) => match git(&["status", "--porcelain", "--untracked-files=no"]) {
            Some(s) if s.is_empty() => head,
            _ => format!("{head} with uncommitted changes"),
        },
        None => "unknown (not a git checkout)".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_section_replaces_only_itself() {
        let doc = format!("# B\n\nbefore\n{BEGIN}\nold table\n{END}\nafter\n");
        let new = replace_section(&doc, &format!("{BEGIN}\nnew\n{END}\n")).unwrap();
        assert_eq!(new, format!("# B\n\nbefore\n{BEGIN}\nnew\n{END}\nafter\n"));
        // Without markers it goes at the end, under a heading of its own.
        let new = replace_section("# B\ntext", "S\n").unwrap();
        assert_eq!(
            new,
            "# B\ntext\n\n## QoR sweep: `motionhdl synth --sweep`\n\nS\n"
        );
        // One marker alone, or the two swapped, is refused.
        for bad in [format!("{BEGIN}\n"), format!("{END}\n{BEGIN}\n")] {
            assert!(replace_section(&bad, "S\n")
                .unwrap_err()
                .contains("out of order"));
        }
    }

    #[test]
    fn lists_are_checked_value_by_value() {
        assert_eq!(
            parse_list("axes", "1, 4,16", 1..=16).unwrap(),
            vec![1, 4, 16]
        );
        for bad in ["0", "17", "4,x", "", "4,,8"] {
            let e = parse_list("axes", bad, 1..=16).unwrap_err();
            assert_eq!(e.exit_code, 2);
            assert!(
                e.message.contains("--axes") && e.message.contains("1..=16"),
                "{}",
                e.message
            );
        }
    }

    #[test]
    fn a_design_that_does_not_fit_says_what_it_needs() {
        let row = Row {
            target: Target::Ice40Hx8k,
            design: "board top, 8 axes".into(),
            seed: 2,
            outcome: Outcome::NoFit {
                used: 11_520,
                available: 7680,
            },
        };
        assert_eq!(
            line(&row),
            "| ice40-hx8k | board top, 8 axes | 2 | does not fit: 11520 / 7680 needed at packing (150 %) | | | | | | – |\n"
        );
        // Every line has the header's ten columns.
        assert_eq!(
            line(&row).matches('|').count(),
            header().lines().next().unwrap().matches('|').count()
        );
    }
}
