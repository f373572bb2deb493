//! Writing outputs so that nothing is ever half-written: files go to a
//! temporary name in the same directory and are renamed into place; a
//! directory tree is built beside its destination and swapped in whole.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

fn sibling(path: &Path, tag: &str) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{tag}-{}", std::process::id()))
}

/// Writes one file atomically.
pub fn write_file(path: &Path, contents: &[u8]) -> io::Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        fs::create_dir_all(parent)?;
    }
    let tmp = sibling(path, "tmp");
    fs::write(&tmp, contents)?;
    fs::rename(&tmp, path).inspect_err(|_| {
        let _ = fs::remove_file(&tmp);
    })
}

/// Replaces directory `dir` with exactly `files` (paths relative to `dir`).
/// The new tree is complete before it replaces the old one.
pub fn replace_dir(dir: &Path, files: &[(PathBuf, Vec<u8>)]) -> io::Result<()> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
        fs::create_dir_all(parent)?;
    }
    let staging = sibling(dir, "tmp");
    let _ = fs::remove_dir_all(&staging);
    let build = || -> io::Result<()> {
        for (rel, data) in files {
            let p = staging.join(rel);
            fs::create_dir_all(p.parent().expect("relative file path has a parent"))?;
            fs::write(p, data)?;
        }
        Ok(())
    };
    if let Err(e) = build() {
        let _ = fs::remove_dir_all(&staging);
        return Err(e);
    }
    if dir.exists() {
        let old = sibling(dir, "old");
        let _ = fs::remove_dir_all(&old);
        fs::rename(dir, &old)?;
        if let Err(e) = fs::rename(&staging, dir) {
            let _ = fs::rename(&old, dir);
            return Err(e);
        }
        fs::remove_dir_all(&old)?;
    } else {
        fs::rename(&staging, dir)?;
    }
    Ok(())
}
