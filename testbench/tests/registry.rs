//! The registry is the one list of checks: every block's checks module in
//! `src/checks/` contributes its `all` to a group there, and every module
//! is named as a block's file in `hdl/src/`.

use std::fs;
use std::path::Path;

fn modules(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_none_or(|x| x == "rs"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .filter(|n| n != "mod")
        .collect();
    names.sort();
    names.dedup();
    names
}

#[test]
fn every_checks_module_is_a_block_and_in_the_registry() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let checks = modules(&root.join("src/checks"));
    let blocks = modules(&root.join("../hdl/src"));
    let registry = fs::read_to_string(root.join("src/registry.rs")).unwrap();
    assert_eq!(checks.len(), 15, "{checks:?}");
    for m in &checks {
        assert!(
            blocks.contains(m),
            "src/checks/{m} names no file in hdl/src"
        );
        assert!(
            [",", "("]
                .iter()
                .any(|end| registry.contains(&format!("{m}::all{end}"))),
            "src/registry.rs does not run {m}::all"
        );
    }
    // The rule can fail: a module named after no block is caught.
    assert!(!blocks.contains(&"selector".to_string()));
}
