//! Replacing `generate`'s output directory.
//!
//! A directory is replaced only when it holds a previous motionhdl output and
//! nothing else: the files its manifest lists, unchanged (or, from before the
//! manifest, files whose first line carries the banner). With `force`, files
//! motionhdl did not write are carried into the new directory untouched
//! (hard links: the same files), and the run refuses if one of them stands
//! where it would write.
//!
//! The new tree is built and synced under a staging name beside the
//! directory, then swapped with it by one `renameat2(RENAME_EXCHANGE)`, so at
//! every instant the path holds the complete old or the complete new output;
//! the old tree, now under the staging name, is removed afterwards.
//! Interruptions stop only before the swap (see [`crate::interrupt`]).

use super::{manifest, parent_of, resolve, sweep_leftovers, sync_dir, DirLock, RANDOM_LEN};
use crate::{interrupt, CliError};
use std::collections::{BTreeMap, BTreeSet};
use std::fs::{self, FileType};
use std::io;
use std::path::{Path, PathBuf};

/// What protects a run's surroundings: `force`, and the configuration file
/// (its directory is never an output).
#[derive(Clone, Copy, Default)]
pub struct Options<'a> {
    pub force: bool,
    pub config: Option<&'a Path>,
}

/// What a run did.
#[derive(Debug)]
pub struct Written {
    /// Files motionhdl did not write, kept (with `force`).
    pub kept: usize,
}

/// One entry of an existing output directory.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Owner {
    Ours,
    OursChanged,
    Foreign,
}

struct Entry {
    rel: String,
    kind: FileType,
    owner: Owner,
}

/// Checks, before anything is computed, that `out` may receive output:
/// resolves it, applies the refusals and looks at what it holds.
pub fn check(out: &Path, opts: Options) -> Result<PathBuf, CliError> {
    let dir = resolve(out)?;
    refuse_special(out, &dir, opts)?;
    if dir.is_dir() {
        let entries = survey(&dir).map_err(|e| read_error(&dir, e))?;
        judge(out, &entries, opts.force, &BTreeSet::new())?;
    }
    Ok(dir)
}

/// Replaces `out` with exactly `files` plus their manifest.
pub fn replace(
    out: &Path,
    files: &[(PathBuf, Vec<u8>)],
    opts: Options,
) -> Result<Written, CliError> {
    let files = manifest::with_manifest(files);
    // What the directory holds is judged once, under the lock below (the
    // CLI has already run `check` before computing the files).
    let dir = resolve(out)?;
    refuse_special(out, &dir, opts)?;
    let parent = parent_of(&dir).to_path_buf();
    let lock = DirLock::acquire(&parent).map_err(|e| write_error(&parent, e))?;
    interrupt::catch();
    let name = dir.file_name().expect("a resolved output has a name");
    sweep_leftovers(&parent, &[name]);
    // Looked at again under the lock, now against the files to write.
    let writing: BTreeSet<String> = files.iter().map(|(p, _)| manifest::slash_path(p)).collect();
    let (keep, mode) = if dir.is_dir() {
        let entries = survey(&dir).map_err(|e| read_error(&dir, e))?;
        let keep = judge(out, &entries, opts.force, &writing)?;
        let mode = fs::metadata(&dir)
            .map_err(|e| read_error(&dir, e))?
            .permissions();
        (keep, mode)
    } else {
        (Vec::new(), super::default_mode(0o777))
    };
    let staging = tempfile::Builder::new()
        .prefix(super::STAGING_PREFIX)
        .rand_bytes(RANDOM_LEN)
        .permissions(mode.clone())
        .tempdir_in(&parent)
        .map_err(|e| write_error(&parent, e))?;
    let stage = || -> io::Result<()> {
        fs::set_permissions(staging.path(), mode.clone())?;
        build(staging.path(), &files)?;
        carry_over(&dir, staging.path(), &keep)?;
        sync_tree(staging.path())
    };
    stage().map_err(|e| write_error(&dir, e))?;
    interrupt::checkpoint("generate-staged")
        .map_err(|sig| interrupt::interrupted(sig, &format!("{} is as it was", out.display())))?;
    let staged = staging.keep();
    let old = swap(&staged, &dir).map_err(|e| {
        let _ = fs::remove_dir_all(&staged);
        write_error(&dir, e)
    })?;
    let _ = sync_dir(&parent);
    interrupt::hook("generate-swapped");
    remove_tree(&old).map_err(|e| {
        CliError::failure(format!(
            "the new output is in {}, but its old copy {} could not be removed: {e}",
            dir.display(),
            old.display()
        ))
    })?;
    drop(lock);
    if let Some(sig) = interrupt::pending() {
        return Err(interrupt::interrupted(
            sig,
            &format!("{} already holds the complete new output", out.display()),
        ));
    }
    Ok(Written { kept: keep.len() })
}

fn read_error(dir: &Path, e: io::Error) -> CliError {
    CliError::failure(format!("cannot read {}: {e}", dir.display()))
}

fn write_error(dir: &Path, e: io::Error) -> CliError {
    CliError::failure(format!("cannot write {}: {e}", dir.display()))
}

/// The outputs that are refused whatever they hold.
fn refuse_special(out: &Path, dir: &Path, opts: Options) -> Result<(), CliError> {
    let refuse = |why: String| {
        let shown = if out == dir {
            out.display().to_string()
        } else {
            format!("{} ({})", out.display(), dir.display())
        };
        Err(CliError::input(format!(
            "refusing to write into {shown}: {why}; give a new or empty directory, \
             e.g. --out generated"
        )))
    };
    if dir.parent().is_none() {
        return refuse("it is the root directory".into());
    }
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::input(format!(
            "cannot write into {}: it is a file, not a directory",
            out.display()
        )));
    }
    let holds = |inner: &Path, what: &str| {
        let inner = fs::canonicalize(inner).ok()?;
        if inner == dir {
            Some(format!("it is {what}"))
        } else if inner.starts_with(dir) {
            Some(format!("it holds {what} ({})", inner.display()))
        } else {
            None
        }
    };
    if let Some(why) = std::env::current_dir()
        .ok()
        .and_then(|cwd| holds(&cwd, "the current directory"))
    {
        return refuse(why);
    }
    if let Some(why) =
        std::env::var_os("HOME").and_then(|h| holds(Path::new(&h), "your home directory"))
    {
        return refuse(why);
    }
    if let Some(cfg) = opts.config {
        if let Some(why) = holds(cfg, "the configuration file") {
            return refuse(why);
        }
    }
    if fs::symlink_metadata(dir.join(".git")).is_ok() {
        return refuse("it is the root of a repository (it has .git)".into());
    }
    Ok(())
}

/// Every entry below `dir` (not following links), sorted, with its owner.
fn survey(dir: &Path) -> io::Result<Vec<Entry>> {
    let mut found = Vec::new();
    let mut stack = vec![(dir.to_path_buf(), String::new())];
    while let Some((path, rel)) = stack.pop() {
        for e in fs::read_dir(&path)? {
            let e = e?;
            let name = e.file_name().to_string_lossy().into_owned();
            let rel = if rel.is_empty() {
                name
            } else {
                format!("{rel}/{name}")
            };
            let kind = e.file_type()?;
            if kind.is_dir() {
                stack.push((e.path(), rel.clone()));
            }
            found.push((rel, kind));
        }
    }
    found.sort_by(|a, b| a.0.cmp(&b.0));
    let listed = fs::read(dir.join(manifest::FILE_NAME))
        .ok()
        .and_then(|t| manifest::parse(&t));
    let mut entries = Vec::new();
    for (rel, kind) in &found {
        let owner = if kind.is_dir() {
            Owner::Foreign // settled below, from what it holds
        } else {
            file_owner(dir, rel, *kind, listed.as_ref())?
        };
        entries.push(Entry {
            rel: rel.clone(),
            kind: *kind,
            owner,
        });
    }
    let owned: Vec<String> = entries
        .iter()
        .filter(|e| e.owner != Owner::Foreign)
        .map(|e| e.rel.clone())
        .collect();
    for e in entries.iter_mut().filter(|e| e.kind.is_dir()) {
        let prefix = format!("{}/", e.rel);
        if owned.iter().any(|o| o.starts_with(&prefix)) {
            e.owner = Owner::Ours;
        }
    }
    Ok(entries)
}

fn file_owner(
    dir: &Path,
    rel: &str,
    kind: FileType,
    listed: Option<&BTreeMap<String, String>>,
) -> io::Result<Owner> {
    if !kind.is_file() {
        return Ok(Owner::Foreign);
    }
    let path = dir.join(rel);
    Ok(match listed {
        Some(_) if rel == manifest::FILE_NAME => Owner::Ours,
        Some(list) => match list.get(rel) {
            Some(hash) if *hash == manifest::sha256_hex(&fs::read(&path)?) => Owner::Ours,
            Some(_) => Owner::OursChanged,
            None => Owner::Foreign,
        },
        // Output from before the manifest: every file carries the banner.
        None if manifest::has_marker(&super::head(&path)?) => Owner::Ours,
        None => Owner::Foreign,
    })
}

/// Applies the ownership rules; returns the foreign entries to keep (only
/// with `force`). `writing` holds the paths about to be written (empty for
/// the early check, which cannot know them yet).
fn judge(
    out: &Path,
    entries: &[Entry],
    force: bool,
    writing: &BTreeSet<String>,
) -> Result<Vec<(String, FileType)>, CliError> {
    let shown = |e: &Entry| {
        if e.kind.is_dir() {
            format!("{}/", e.rel)
        } else {
            e.rel.clone()
        }
    };
    let foreign: Vec<&Entry> = entries
        .iter()
        .filter(|e| e.owner == Owner::Foreign)
        .collect();
    if let (false, Some(first)) = (force, foreign.first()) {
        return Err(CliError::input(format!(
            "refusing to replace {}: it holds {} file(s) motionhdl did not write (first: {}); \
             give a new or empty directory, or --force to write beside them (they are kept)",
            out.display(),
            foreign.iter().filter(|e| !e.kind.is_dir()).count().max(1),
            shown(first)
        )));
    }
    if let (false, Some(changed)) = (
        force,
        entries.iter().find(|e| e.owner == Owner::OursChanged),
    ) {
        return Err(CliError::input(format!(
            "refusing to replace {}: {} was changed since motionhdl wrote it; save your \
             changes elsewhere, or --force to overwrite motionhdl's files (other files are kept)",
            out.display(),
            changed.rel
        )));
    }
    let dirs_needed: BTreeSet<String> = writing
        .iter()
        .flat_map(|w| {
            let parts: Vec<&str> = w.split('/').collect();
            (1..parts.len()).map(move |n| parts[..n].join("/"))
        })
        .collect();
    let mut keep = Vec::new();
    for e in foreign {
        let in_the_way = if e.kind.is_dir() {
            writing.contains(&e.rel)
        } else {
            writing.contains(&e.rel) || dirs_needed.contains(&e.rel)
        };
        if in_the_way {
            return Err(CliError::input(format!(
                "refusing to write {}: {} there is not motionhdl's and would be replaced \
                 (even with --force only motionhdl's own files are replaced); move it away",
                out.join(&e.rel).display(),
                if e.kind.is_dir() {
                    "the directory"
                } else {
                    "the file"
                }
            )));
        }
        // A foreign directory is kept whole through its entries.
        let empty_dir = e.kind.is_dir()
            && !entries
                .iter()
                .any(|o| o.rel.starts_with(&format!("{}/", e.rel)));
        if !e.kind.is_dir() || empty_dir {
            keep.push((e.rel.clone(), e.kind));
        }
    }
    Ok(keep)
}

/// Writes and syncs every file under `root`.
fn build(root: &Path, files: &[(PathBuf, Vec<u8>)]) -> io::Result<()> {
    for (i, (rel, data)) in files.iter().enumerate() {
        let path = root.join(rel);
        fs::create_dir_all(path.parent().expect("a file below the root has a parent"))?;
        let mut f = fs::File::create(&path)?;
        io::Write::write_all(&mut f, data)?;
        f.sync_all()?;
        if i == 0 {
            interrupt::hook("generate-staging");
        }
    }
    Ok(())
}

/// Links the kept foreign entries of `old` into `new` at the same places.
fn carry_over(old: &Path, new: &Path, keep: &[(String, FileType)]) -> io::Result<()> {
    for (rel, kind) in keep {
        let (from, to) = (old.join(rel), new.join(rel));
        fs::create_dir_all(parent_of(&to))?;
        if kind.is_dir() {
            fs::create_dir_all(&to)?;
        } else if kind.is_symlink() {
            std::os::unix::fs::symlink(fs::read_link(&from)?, &to)?;
        } else if fs::hard_link(&from, &to).is_err() {
            fs::copy(&from, &to)?;
        }
    }
    Ok(())
}

/// Syncs every directory of a tree (files were synced as written).
fn sync_tree(root: &Path) -> io::Result<()> {
    for e in fs::read_dir(root)? {
        let e = e?;
        if e.file_type()?.is_dir() {
            sync_tree(&e.path())?;
        }
    }
    sync_dir(root)
}

/// Puts the tree at `staging` in `dir`'s place; returns where the old tree
/// is now (under a staging name; nothing there when `dir` did not exist).
fn swap(staging: &Path, dir: &Path) -> io::Result<PathBuf> {
    use rustix::fs::{renameat_with, RenameFlags, CWD};
    if !dir.exists() {
        renameat_with(CWD, staging, CWD, dir, RenameFlags::NOREPLACE)?;
        return Ok(staging.to_path_buf());
    }
    match renameat_with(CWD, staging, CWD, dir, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(staging.to_path_buf()),
        // A file system without the exchange: two renames, with a moment
        // between them in which the path is missing.
        Err(rustix::io::Errno::INVAL) | Err(rustix::io::Errno::NOSYS) => {
            let aside = tempfile::Builder::new()
                .prefix(super::STAGING_PREFIX)
                .rand_bytes(RANDOM_LEN)
                .tempdir_in(parent_of(dir))?
                .keep();
            fs::rename(dir, &aside)?;
            if let Err(e) = fs::rename(staging, dir) {
                fs::rename(&aside, dir)?;
                return Err(e);
            }
            Ok(aside)
        }
        Err(e) => Err(e.into()),
    }
}

/// Removes the old tree file by file (a test hook runs after the first).
fn remove_tree(root: &Path) -> io::Result<()> {
    if !root.exists() {
        return Ok(());
    }
    let mut first = true;
    let mut stack = vec![root.to_path_buf()];
    let mut dirs = Vec::new();
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d)? {
            let e = e?;
            if e.file_type()?.is_dir() {
                stack.push(e.path());
            } else {
                fs::remove_file(e.path())?;
                if std::mem::take(&mut first) {
                    interrupt::hook("generate-cleaning");
                }
            }
        }
        dirs.push(d);
    }
    for d in dirs.iter().rev() {
        fs::remove_dir(d)?;
    }
    Ok(())
}
