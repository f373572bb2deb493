//! Writing outputs so that nothing a user has is lost and nothing is ever
//! half-written.
//!
//! - Paths are resolved first and refused when replacing them could take a
//!   user's work with them (the current, home or root directory, a
//!   repository, the directory of the configuration file).
//! - Everything is staged under a short hidden name beside its destination
//!   (`.motionhdl-staging.XXXXXXXX`, `.motionhdl-partial.XXXXXXXX`), so a
//!   staging name fits wherever the final name fits, and moved into place by
//!   one rename; a directory is swapped in whole (see [`generated_dir`]).
//! - Work in one directory holds an exclusive lock on it, so a staging name
//!   found there by a run holding the lock is a leftover of a run that died,
//!   and is removed.

pub mod generated_dir;
pub mod manifest;

use crate::{interrupt, CliError};
use std::ffi::OsStr;
use std::fs::{self, File, Permissions};
use std::io::{self, Read, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// The name prefix of a directory tree being built beside its destination.
pub const STAGING_PREFIX: &str = ".motionhdl-staging.";
/// The name prefix of a file being written beside its destination.
pub const PARTIAL_PREFIX: &str = ".motionhdl-partial.";
const RANDOM_LEN: usize = 8;

/// An absolute form of `path` with every part that exists resolved
/// (symbolic links, `.` and `..`), the rest appended as spelled.
pub fn resolve(path: &Path) -> Result<PathBuf, CliError> {
    if path.as_os_str().is_empty() {
        return Err(CliError::input("the output path is empty"));
    }
    if let Ok(real) = fs::canonicalize(path) {
        return Ok(real);
    }
    if fs::symlink_metadata(path).is_ok() {
        return Err(CliError::input(format!(
            "cannot write {}: it is a symbolic link to nothing",
            path.display()
        )));
    }
    let name = path.file_name().ok_or_else(|| {
        CliError::input(format!(
            "cannot write {}: `..` after a directory that does not exist",
            path.display()
        ))
    })?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => resolve(p)?,
        _ => std::env::current_dir()
            .map_err(|e| CliError::failure(format!("cannot read the current directory: {e}")))?,
    };
    Ok(parent.join(name))
}

/// The parent of a resolved path (every resolved path but `/` has one).
pub fn parent_of(path: &Path) -> &Path {
    path.parent().unwrap_or(Path::new("/"))
}

/// An exclusive lock on a directory, held while staging names in it are
/// made, renamed or swept; released when dropped.
pub struct DirLock(#[allow(dead_code)] File);

impl DirLock {
    /// Creates `dir` (and its parents) if missing, then waits for its lock.
    pub fn acquire(dir: &Path) -> io::Result<Self> {
        fs::create_dir_all(dir)?;
        let handle = File::open(dir)?;
        rustix::fs::flock(&handle, rustix::fs::FlockOperation::LockExclusive)?;
        Ok(Self(handle))
    }
}

/// True for a name this module stages under.
fn is_staging_name(name: &str) -> bool {
    [STAGING_PREFIX, PARTIAL_PREFIX].iter().any(|prefix| {
        name.strip_prefix(prefix).is_some_and(|rest| {
            rest.len() == RANDOM_LEN && rest.bytes().all(|b| b.is_ascii_alphanumeric())
        })
    })
}

/// True for the staging names of motionhdl before 0.1.0's manifest,
/// `.NAME.tmp-PID` and `.NAME.old-PID`, of one of `names`, whose process
/// is gone.
fn is_old_style_leftover(name: &str, names: &[&OsStr]) -> bool {
    let Some((stem, pid)) = name.strip_prefix('.').and_then(|n| n.rsplit_once('-')) else {
        return false;
    };
    let Some(base) = stem
        .strip_suffix(".tmp")
        .or_else(|| stem.strip_suffix(".old"))
    else {
        return false;
    };
    let Some(pid) = pid
        .parse::<i32>()
        .ok()
        .and_then(rustix::process::Pid::from_raw)
    else {
        return false;
    };
    let gone = rustix::process::test_kill_process(pid) == Err(rustix::io::Errno::SRCH);
    gone && names.iter().any(|n| *n == OsStr::new(base))
}

/// Removes what runs that died left in `dir`: staging names, and old-style
/// ones of `names`. The caller holds `dir`'s [`DirLock`]. Returns how many.
pub fn sweep_leftovers(dir: &Path, names: &[&OsStr]) -> usize {
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if !is_staging_name(&name) && !is_old_style_leftover(&name, names) {
            continue;
        }
        let path = entry.path();
        let gone = match entry.file_type() {
            Ok(t) if t.is_dir() => fs::remove_dir_all(&path),
            _ => fs::remove_file(&path),
        };
        if gone.is_ok() {
            removed += 1;
        }
    }
    removed
}

/// The mode a new file or directory gets from the process's umask.
pub fn default_mode(full: u32) -> Permissions {
    use rustix::fs::Mode;
    let mask = rustix::process::umask(Mode::from_raw_mode(0o022));
    rustix::process::umask(mask);
    Permissions::from_mode(full & !mask.as_raw_mode())
}

/// Reads at most `limit` bytes of `path`: `Err` names the limit when the
/// file is longer (so `/dev/zero` cannot exhaust memory).
pub fn read_bounded(path: &Path, limit: u64) -> io::Result<Result<Vec<u8>, u64>> {
    let mut data = Vec::new();
    File::open(path)?.take(limit + 1).read_to_end(&mut data)?;
    Ok(if data.len() as u64 > limit {
        Err(limit)
    } else {
        Ok(data)
    })
}

/// The first bytes of a file, enough to see its first line's banner.
pub fn head(path: &Path) -> io::Result<Vec<u8>> {
    let mut data = Vec::new();
    File::open(path)?.take(512).read_to_end(&mut data)?;
    Ok(data)
}

/// Checks that each of `paths` may be written as a single file: not a
/// directory, not one path twice, and an existing file only when motionhdl
/// wrote it (its first line has the banner) or with `force`. Returns each
/// resolved path with the mode of the file it replaces.
pub fn check_files(
    paths: &[&Path],
    force: bool,
) -> Result<Vec<(PathBuf, Option<Permissions>)>, CliError> {
    let mut resolved: Vec<PathBuf> = Vec::new();
    for path in paths {
        let target = resolve(path)?;
        if resolved.contains(&target) {
            return Err(CliError::input(format!(
                "{} would be written twice (a trace and its .gtkw save file or .svg plot): \
                 give the trace a name ending in .vcd",
                path.display()
            )));
        }
        resolved.push(target);
    }
    paths
        .iter()
        .zip(resolved)
        .map(|(path, target)| {
            let old_mode = existing_file_mode(path, &target, force)?;
            Ok((target, old_mode))
        })
        .collect()
}

/// Writes single files (a trace and its save file) so that each is either
/// its old or its new self: every file is staged and synced first, then all
/// are renamed into place. The rules of [`check_files`] apply.
pub fn write_files(files: &[(PathBuf, Vec<u8>)], force: bool) -> Result<(), CliError> {
    let paths: Vec<&Path> = files.iter().map(|(p, _)| p.as_path()).collect();
    let targets = check_files(&paths, force)?;
    let dir = parent_of(&targets[0].0).to_path_buf();
    let fail = |what: &Path, e: io::Error| {
        CliError::failure(format!("cannot write {}: {e}", what.display()))
    };
    let _lock = DirLock::acquire(&dir).map_err(|e| fail(&dir, e))?;
    interrupt::catch();
    let names: Vec<&OsStr> = targets.iter().filter_map(|t| t.0.file_name()).collect();
    sweep_leftovers(&dir, &names);
    let mut staged = Vec::new();
    for ((target, old_mode), (_, data)) in targets.iter().zip(files) {
        let mode = old_mode.clone().unwrap_or_else(|| default_mode(0o666));
        fs::create_dir_all(parent_of(target)).map_err(|e| fail(target, e))?;
        let tmp = stage_file(parent_of(target), data, mode).map_err(|e| fail(target, e))?;
        staged.push((tmp, target));
        interrupt::checkpoint("write-staged").map_err(|sig| interrupted_untouched(sig, &paths))?;
    }
    for (i, (tmp, target)) in staged.into_iter().enumerate() {
        tmp.persist(target).map_err(|e| fail(target, e.error))?;
        if i == 0 {
            interrupt::hook("write-renamed");
        }
    }
    sync_dir(&dir).map_err(|e| fail(&dir, e))?;
    match interrupt::pending() {
        Some(sig) => Err(interrupt::interrupted(
            sig,
            "every file was already written",
        )),
        None => Ok(()),
    }
}

fn interrupted_untouched(sig: i32, paths: &[&Path]) -> CliError {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    interrupt::interrupted(sig, &format!("{} left as they were", names.join(" and ")))
}

/// The mode of the file `target` replaces, after checking it may be
/// replaced; `None` when there is none.
fn existing_file_mode(
    given: &Path,
    target: &Path,
    force: bool,
) -> Result<Option<Permissions>, CliError> {
    let Ok(meta) = fs::metadata(target) else {
        return Ok(None);
    };
    if meta.is_dir() {
        return Err(CliError::input(format!(
            "cannot write {}: it is a directory",
            given.display()
        )));
    }
    let ours = meta.is_file() && head(target).is_ok_and(|h| manifest::has_marker(&h));
    if !ours && !force {
        return Err(CliError::input(format!(
            "refusing to overwrite {}: motionhdl did not write it (its first line has no \
             `{}` banner); choose another name, or --force to replace it",
            given.display(),
            manifest::MARKER.trim_end()
        )));
    }
    Ok(Some(meta.permissions()))
}

/// Writes `data` to a new synced file under a staging name in `dir`.
pub fn stage_file(
    dir: &Path,
    data: &[u8],
    mode: Permissions,
) -> io::Result<tempfile::NamedTempFile> {
    let mut tmp = tempfile::Builder::new()
        .prefix(PARTIAL_PREFIX)
        .rand_bytes(RANDOM_LEN)
        .permissions(mode.clone())
        .tempfile_in(dir)?;
    tmp.write_all(data)?;
    // The umask narrowed the mode at creation; an old file's mode is kept.
    tmp.as_file().set_permissions(mode)?;
    tmp.as_file().sync_all()?;
    Ok(tmp)
}

/// Makes a directory's entries durable (after renames into it).
pub fn sync_dir(dir: &Path) -> io::Result<()> {
    File::open(dir)?.sync_all()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn staging_names_are_recognised_exactly() {
        assert!(is_staging_name(".motionhdl-staging.a1B2c3D4"));
        assert!(is_staging_name(".motionhdl-partial.ZZZZ0000"));
        assert!(!is_staging_name(".motionhdl-staging.a1B2c3D"));
        assert!(!is_staging_name(".motionhdl-staging.a1B2c3D45"));
        assert!(!is_staging_name(".motionhdl-config"));
        assert!(!is_staging_name("motionhdl-staging.a1B2c3D4"));
    }

    #[test]
    fn old_style_names_need_a_dead_process_and_a_known_name() {
        let names = [OsStr::new("gen")];
        let me = std::process::id();
        assert!(!is_old_style_leftover(&format!(".gen.tmp-{me}"), &names));
        // PID 2^22 + 1 is above Linux's pid_max ceiling: never a process.
        let dead = (1 << 22) + 1;
        assert!(is_old_style_leftover(&format!(".gen.tmp-{dead}"), &names));
        assert!(is_old_style_leftover(&format!(".gen.old-{dead}"), &names));
        assert!(!is_old_style_leftover(
            &format!(".other.tmp-{dead}"),
            &names
        ));
        assert!(!is_old_style_leftover(&format!(".gen.bak-{dead}"), &names));
        assert!(!is_old_style_leftover(".gen.tmp-x", &names));
    }
}
