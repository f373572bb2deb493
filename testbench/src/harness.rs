//! Stepping rust-hdl blocks directly, and reporting checks.

use rust_hdl::prelude::{simulate, Block, Clock, In, Signal};
use std::path::PathBuf;

/// Propagates inputs through combinational logic until nothing changes.
pub fn settle<B: Block>(uut: &mut B) {
    assert!(
        simulate(uut, 1000),
        "circuit did not settle (combinational loop?)"
    );
}

/// One full clock cycle: the rising edge, settled; then the falling edge,
/// driven but left to settle with whatever the caller drives next (its
/// next [`settle`], or this function's next call). The outputs read after
/// it are the settled post-edge values: no block here looks at the clock's
/// level, only at its rising edge. That saves one of the three settles a
/// clock took, each a pass over the block's whole hierarchy per level of
/// it. `clock` selects the block's clock input.
pub fn cycle<B: Block>(uut: &mut B, clock: fn(&mut B) -> &mut Signal<In, Clock>) {
    if clock(uut).val().clk {
        // The last call's falling edge, with nothing settled since.
        settle(uut);
    }
    clock(uut).next = Clock::from(true);
    settle(uut);
    clock(uut).next = Clock::from(false);
}

/// The outcome of one check: how many cases it covered against how many it
/// had to cover, and every mismatch (with the inputs that produced it).
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub block: String,
    pub check: String,
    pub covered: u64,
    pub expected: u64,
    pub failures: Vec<String>,
    /// Why the check did not run (a missing external tool outside CI).
    pub skipped: Option<String>,
}

impl CheckReport {
    pub fn new(block: &str, check: &str, expected: u64) -> Self {
        Self {
            block: block.into(),
            check: check.into(),
            covered: 0,
            expected,
            failures: Vec::new(),
            skipped: None,
        }
    }

    /// Records one case; `failure` is `Some(description)` on a mismatch.
    /// Only the first 20 failures are kept in full.
    pub fn case(&mut self, failure: Option<String>) {
        self.covered += 1;
        if let Some(f) = failure {
            if self.failures.len() < 20 {
                self.failures.push(f);
            } else if self.failures.len() == 20 {
                self.failures.push("… further failures not shown".into());
            }
        }
    }

    /// Records that the check could not run.
    pub fn skip(mut self, why: String) -> Self {
        self.skipped = Some(why);
        self
    }

    /// Passed, or skipped for a missing tool outside CI. Under CI a check
    /// that did not run has not passed.
    pub fn acceptable(&self) -> bool {
        self.passed() || (self.skipped.is_some() && self.failures.is_empty() && !in_ci())
    }

    pub fn passed(&self) -> bool {
        self.skipped.is_none() && self.failures.is_empty() && self.covered == self.expected
    }

    pub fn result(&self) -> String {
        if let Some(why) = &self.skipped {
            format!("SKIPPED ({why})")
        } else if !self.failures.is_empty() {
            format!("FAIL ({} mismatches)", self.failures.len())
        } else if self.covered != self.expected {
            "FAIL (coverage)".into()
        } else {
            "pass".into()
        }
    }

    /// Panics with every failure unless the check passed. A skip is
    /// accepted only outside CI (see [`tool`]).
    pub fn assert_passed(&self) {
        if let Some(why) = &self.skipped {
            assert!(
                !in_ci(),
                "{} / {}: skipped in CI: {why}",
                self.block,
                self.check
            );
            record_skip(&format!("{} / {}: {why}", self.block, self.check));
            return;
        }
        assert!(
            self.failures.is_empty(),
            "{} / {}: {} mismatches:\n{}",
            self.block,
            self.check,
            self.failures.len(),
            self.failures.join("\n")
        );
        assert_eq!(
            self.covered, self.expected,
            "{} / {}: covered {} of {} cases",
            self.block, self.check, self.covered, self.expected
        );
    }
}

/// True when running under CI (the `CI` environment variable is set).
pub fn in_ci() -> bool {
    std::env::var_os("CI").is_some_and(|v| !v.is_empty() && v != "false" && v != "0")
}

/// The environment variable naming the venv that `scripts/install-tools`
/// fills with YoWASP, SymbiYosys, Yices and FuseSoC.
pub const VENV_VAR: &str = "MOTIONHDL_YOWASP_VENV";

/// The tools' venv: `$MOTIONHDL_YOWASP_VENV`, else
/// `$HOME/.cache/motionhdl/yowasp` (where install-tools puts it).
pub fn tools_venv() -> PathBuf {
    match std::env::var_os(VENV_VAR) {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => user_cache().join("yowasp"),
    }
}

/// The venv's `bin/`, the second place [`tool`] looks.
pub fn venv_bin() -> PathBuf {
    tools_venv().join("bin")
}

/// `~/.cache/motionhdl`, where install-tools and the Verilator cache live.
pub fn user_cache() -> PathBuf {
    PathBuf::from(std::env::var_os("HOME").unwrap_or_default()).join(".cache/motionhdl")
}

/// Where tools are looked for: PATH, then the venv's `bin/`, so that the
/// CLI and the tests find what install-tools made without a PATH change.
pub fn tool_dirs() -> Vec<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut dirs: Vec<PathBuf> = std::env::split_paths(&path).collect();
    dirs.push(venv_bin());
    dirs
}

/// Finds an external tool on PATH or in the tools' venv. `Err` names the
/// tool and both places; callers turn that into a skip outside CI and a
/// failure under CI.
pub fn tool(name: &str) -> Result<PathBuf, String> {
    tool_dirs()
        .into_iter()
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
        .ok_or_else(|| format!("`{name}` not found on PATH or in {}", venv_bin().display()))
}

/// Lets a Verilator build reuse earlier compiles across runs: Verilator
/// compiles through `$OBJCACHE`, here ccache (when installed) with its
/// cache under `~/.cache/motionhdl/ccache`, unless the caller set either.
pub fn cache_verilator_build(cmd: &mut std::process::Command) {
    if std::env::var_os("OBJCACHE").is_none() {
        if let Ok(ccache) = tool("ccache") {
            cmd.env("OBJCACHE", ccache);
        }
    }
    if std::env::var_os("CCACHE_DIR").is_none() {
        cmd.env("CCACHE_DIR", user_cache().join("ccache"));
    }
}

/// The directory the processes of one run share results through
/// (scripts/test makes a fresh `target/run-cache` for every run): nextest
/// runs each test in a process of its own, and the netlists and traces
/// several tests read would otherwise be made once per process.
pub const RUN_CACHE_VAR: &str = "MOTIONHDL_RUN_CACHE";

/// `make()`, shared through the run's cache when [`RUN_CACHE_VAR`] names
/// one: the file `<dir>/<kind>/<hash of key>` is written whole by a rename
/// and read by later callers instead. Without the variable, or when the
/// file cannot be read, `make` runs; a failure is never cached. The key
/// must hold everything the result depends on but the build itself (one
/// run has one build).
pub fn run_cached<K: std::hash::Hash, E>(
    kind: &str,
    key: &K,
    make: impl FnOnce() -> Result<Vec<u8>, E>,
) -> Result<Vec<u8>, E> {
    use std::hash::Hasher;
    let Some(root) = std::env::var_os(RUN_CACHE_VAR).filter(|d| !d.is_empty()) else {
        return make();
    };
    let mut hash = std::collections::hash_map::DefaultHasher::new();
    key.hash(&mut hash);
    let dir = PathBuf::from(root).join(kind);
    let file = dir.join(format!("{:016x}", hash.finish()));
    if let Ok(bytes) = std::fs::read(&file) {
        return Ok(bytes);
    }
    let bytes = make()?;
    let staged = file.with_extension(format!("{}.tmp", std::process::id()));
    if std::fs::create_dir_all(&dir).is_ok() && std::fs::write(&staged, &bytes).is_ok() {
        let _ = std::fs::rename(&staged, &file);
    }
    Ok(bytes)
}

/// Like [`tool`], for tests: panics under CI when the tool is missing,
/// otherwise prints why the test is skipped and returns `None`.
pub fn require_tool(name: &str) -> Option<PathBuf> {
    match tool(name) {
        Ok(p) => Some(p),
        Err(why) => {
            skip_test(&why);
            None
        }
    }
}

/// [`require_tool`] for each of `names`: `None` (a recorded skip, a
/// failure under CI) at the first one missing.
pub fn require_tools(names: &[&str]) -> Option<()> {
    for name in names {
        require_tool(name)?;
    }
    Some(())
}

/// Like [`require_tool`], for a Rust target's standard library
/// (`rustup target add TARGET`): `None` (a recorded skip, a failure under
/// CI) when the sysroot lacks it.
pub fn require_rust_target(target: &str) -> Option<()> {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let out = std::process::Command::new(rustc)
        .args(["--print", "sysroot"])
        .output()
        .expect("rustc --print sysroot");
    let sysroot = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if sysroot.join("lib/rustlib").join(target).is_dir() {
        return Some(());
    }
    skip_test(&format!(
        "rust target {target} not installed (rustup target add {target})"
    ));
    None
}

/// A test that cannot run here: under CI a failure (CI installs every
/// tool), elsewhere a skip that is recorded for the run's summary.
pub fn skip_test(why: &str) {
    assert!(
        !in_ci(),
        "{why}: CI must install it (scripts/install-tools)"
    );
    record_skip(why);
}

/// Where skips are recorded: `MOTIONHDL_SKIP_LOG`, which `scripts/test`
/// sets and prints at the end of the run (cargo's capture hides a
/// test's own output).
pub const SKIP_LOG_VAR: &str = "MOTIONHDL_SKIP_LOG";

/// Prints a skip and appends it, with the test's name, to the skip log.
pub fn record_skip(what: &str) {
    eprintln!("SKIPPED: {what}");
    if let Some(log) = std::env::var_os(SKIP_LOG_VAR) {
        append_skip(std::path::Path::new(&log), what);
    }
}

/// Appends one line `TEST: WHAT` to `log` (one write, so that tests
/// running in parallel do not interleave within a line).
pub fn append_skip(log: &std::path::Path, what: &str) {
    use std::io::Write;
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let line = format!("{test}: {}\n", what.replace('\n', " "));
    let appended = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
        .and_then(|mut f| f.write_all(line.as_bytes()));
    if let Err(e) = appended {
        eprintln!("cannot record the skip in {}: {e}", log.display());
    }
}

/// xorshift32 (13, 17, 5): one step of the pin stimulus generators whose
/// Verilog copies run in the simulators (`checks::counter_bank::stimulus`,
/// `checks::motion_controller::top_stimulus`);
/// the Verilog testbenches spell out the same three shifts.
pub fn xorshift32(x: &mut u32) -> u32 {
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    *x
}

/// The testbenches' one random generator (xorshift64*), so a seed names
/// the same stimulus in every check. (The pin stimulus generators that
/// also run inside the simulators use [`xorshift32`], which their Verilog
/// twins spell out.)
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9e37_79b9_7f4a_7c15 | 1)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// The generator as a closure, one word per call.
    pub fn stream(seed: u64) -> impl FnMut() -> u64 {
        let mut r = Self::new(seed);
        move || r.next_u64()
    }
    /// Uniform enough below `n` for stimulus (`n` ≪ 2^64).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

/// The cells of a Markdown table in `doc`: the first table after the
/// line `heading` whose header row starts with `header`, one `Vec` of
/// trimmed non-empty cells per body row (docs tests read their pages so).
pub fn doc_table_rows<'a>(doc: &'a str, heading: &str, header: &str) -> Vec<Vec<&'a str>> {
    let section = doc
        .split(heading)
        .nth(1)
        .unwrap_or_else(|| panic!("no {heading:?} in the page"));
    section
        .lines()
        .skip_while(|l| !l.starts_with(header))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            l.split('|')
                .map(str::trim)
                .filter(|c| !c.is_empty())
                .collect()
        })
        .collect()
}

/// One clock of random register traffic on a block: in one clock of
/// `every` a write of a register of `map` (its data from `write_data`,
/// given the register's name), in one a read (an eighth of the time of
/// any word the block decodes, else of a register), else idle.
pub fn random_bus_cycle(
    map: &motionhdl_model::regmap::Block,
    every: u64,
    next: &mut dyn FnMut() -> u64,
    write_data: fn(&str, &mut dyn FnMut() -> u64) -> u32,
) -> motionhdl_model::counter::BusCycle {
    use motionhdl_model::counter::BusCycle;
    let decoded = map.decoded();
    let pick = |next: &mut dyn FnMut() -> u64| decoded[(next() % decoded.len() as u64) as usize];
    match next() % every {
        0 => {
            let (addr, r, _) = pick(next);
            BusCycle::write(addr, write_data(r.name, next))
        }
        1 if next().is_multiple_of(8) => BusCycle::read((next() % (1 << map.address_bits)) as u32),
        1 => BusCycle::read(pick(next).0),
        _ => BusCycle::default(),
    }
}

#[cfg(test)]
mod skip_log_tests {
    use super::append_skip;

    #[test]
    fn a_skip_is_appended_with_the_test_name_on_one_line() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("skipped.txt");
        append_skip(&log, "`iverilog` not found on PATH");
        append_skip(&log, "two\nlines");
        let text = std::fs::read_to_string(&log).unwrap();
        let me = std::thread::current().name().unwrap().to_string();
        assert!(me.ends_with("a_skip_is_appended_with_the_test_name_on_one_line"));
        assert_eq!(
            text,
            format!("{me}: `iverilog` not found on PATH\n{me}: two lines\n")
        );
    }
}
