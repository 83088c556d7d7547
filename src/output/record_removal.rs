//! The next run's side of the output folder's record (`owned_folder.rs`): what the record of an
//! earlier run lists is removed while it is still the object the run made and nobody changed it,
//! each folder moved aside whole before it is emptied.

use super::folder::write_error;
use super::record::{components, io, mtime_ns, refusal, Entry, Kind, LARGEST_RECORD, RECORD};
use crate::error::Error;
use rustix::fs::{AtFlags, FileType, Mode, OFlags};
use std::collections::BTreeMap;
use std::io::Read;
use std::os::fd::OwnedFd;
use std::path::Path;

/// The name a recorded folder takes while it is being removed, beside its place: a run killed
/// while removing an earlier run's results never leaves a folder half emptied under its own name.
fn removal_name(name: &str) -> String {
    format!(".partial-removed-{name}")
}

/// Open the folders on the way to `names`' last component, none of them a link.
fn walk(root: &OwnedFd, names: &[&str]) -> Option<OwnedFd> {
    let mut fd: Option<OwnedFd> = None;
    for name in names {
        let parent: &OwnedFd = fd.as_ref().unwrap_or(root);
        let flags = OFlags::DIRECTORY | OFlags::RDONLY | OFlags::NOFOLLOW | OFlags::CLOEXEC;
        fd = Some(rustix::fs::openat(parent, *name, flags, Mode::empty()).ok()?);
    }
    fd.or_else(|| {
        rustix::fs::openat(root, ".", OFlags::DIRECTORY | OFlags::RDONLY | OFlags::CLOEXEC, Mode::empty()).ok()
    })
}

/// Whether `stat` is the object `entry` records: the same device, inode and kind; or, for a
/// temporary name noted before it was made, an object of that kind (not a link) under that name.
fn is_recorded(entry: &Entry, stat: &rustix::fs::Stat) -> bool {
    let kind = FileType::from_raw_mode(stat.st_mode);
    let same_kind = match entry.kind {
        Kind::File => kind == FileType::RegularFile,
        Kind::Folder => kind == FileType::Directory,
    };
    let temporary = entry.path.rsplit('/').next().is_some_and(|n| n.starts_with(".partial-"));
    same_kind
        && ((entry.pending && temporary) || (!entry.pending && stat.st_dev == entry.dev && stat.st_ino == entry.ino))
}

/// The line of `lines` (a path's) that the object `stat` is, the last one that says most.
fn recorded<'a>(lines: &'a [Entry], stat: &rustix::fs::Stat) -> Option<&'a Entry> {
    let matching: Vec<&Entry> = lines.iter().filter(|e| is_recorded(e, stat)).collect();
    matching.iter().rev().find(|e| e.size.is_some()).or(matching.last()).copied()
}

fn unchanged(entry: &Entry, stat: &rustix::fs::Stat) -> bool {
    entry.size.is_none_or(|s| s == stat.st_size as u64) && entry.mtime_ns.is_none_or(|t| t == mtime_ns(stat))
}

/// Whether the file at `rel` is an index that names other files of the run (ParaView's and the
/// XDMF reader's entry points).
fn lists_others(rel: &str) -> bool {
    rel.ends_with(".xdmf") || rel.ends_with(".pvd")
}

/// Remove what the record in `root` lists and is unchanged: first the indexes that name other
/// files ([`lists_others`]), then each recorded folder is moved
/// aside whole (to [`removal_name`]), shallowest first, then the files are removed, deepest first,
/// then the folders, once empty. Returns the files an earlier run wrote that have changed since
/// (and then removes nothing).
pub(super) fn remove_recorded(root: &OwnedFd, path: &Path, inputs: &[(u64, u64)]) -> Result<Vec<String>, Error> {
    let file =
        match rustix::fs::openat(root, RECORD, OFlags::RDONLY | OFlags::NOFOLLOW | OFlags::CLOEXEC, Mode::empty()) {
            Ok(fd) => std::fs::File::from(fd),
            Err(rustix::io::Errno::NOENT) => return Ok(Vec::new()),
            Err(rustix::io::Errno::LOOP) => {
                return Err(refusal(&path.join(RECORD), "it is a link, and geoslip does not read through links"))
            }
            Err(e) => return Err(Error::Write { path: path.join(RECORD), source: io(e) }),
        };
    let mut text = Vec::new();
    file.take(LARGEST_RECORD).read_to_end(&mut text).map_err(write_error(&path.join(RECORD)))?;
    let mut entries: BTreeMap<String, Vec<Entry>> = BTreeMap::new();
    for line in text.split(|&b| b == b'\n') {
        if let Ok(entry) = serde_json::from_slice::<Entry>(line) {
            if components(&entry.path).is_ok() {
                entries.entry(entry.path.clone()).or_default().push(entry);
            }
        }
    }
    let is_input = |stat: &rustix::fs::Stat| inputs.contains(&(stat.st_dev, stat.st_ino));
    let stat_at = |rel: &str| -> Option<(OwnedFd, rustix::fs::Stat)> {
        let names = components(rel).ok()?;
        let (last, above) = names.split_last()?;
        let parent = walk(root, above)?;
        let stat = rustix::fs::statat(&parent, *last, AtFlags::SYMLINK_NOFOLLOW).ok()?;
        Some((parent, stat))
    };
    // a file of the earlier run that was changed since stops the run before anything is removed
    let mut changed = Vec::new();
    for (rel, lines) in &entries {
        if let Some((_, stat)) = stat_at(rel) {
            if let Some(entry) = recorded(lines, &stat) {
                if entry.kind == Kind::File && !is_input(&stat) && !unchanged(entry, &stat) {
                    changed.push(rel.clone());
                }
            }
        }
    }
    if !changed.is_empty() {
        return Ok(changed);
    }
    // remove what is at `current` if it is what `lines` recorded, unchanged and no input
    let remove = |current: &str, lines: &[Entry]| -> Result<(), Error> {
        let Some((parent, stat)) = stat_at(current) else { return Ok(()) };
        let Some(entry) = recorded(lines, &stat) else { return Ok(()) };
        if is_input(&stat) || !unchanged(entry, &stat) {
            return Ok(());
        }
        let last = current.rsplit('/').next().unwrap_or(current);
        let flags = if entry.kind == Kind::Folder { AtFlags::REMOVEDIR } else { AtFlags::empty() };
        match rustix::fs::unlinkat(&parent, last, flags) {
            // a folder that holds what the run did not make stays, with it
            Ok(())
            | Err(rustix::io::Errno::NOENT)
            | Err(rustix::io::Errno::NOTEMPTY)
            | Err(rustix::io::Errno::EXIST) => Ok(()),
            Err(e) => Err(Error::Write { path: path.join(current), source: io(e) }),
        }
    };
    // the indexes go first (`results.xdmf`, `results.pvd`: files that list others), so that a run
    // killed in the middle of this never leaves an index naming a file already removed
    for (rel, lines) in &entries {
        if lists_others(rel) && lines.iter().all(|e| e.kind == Kind::File) {
            remove(rel, lines)?;
        }
    }
    // where each recorded folder is now: its own place, or the name it was moved aside to (each
    // move is in the names the moves before it left)
    let mut moved: Vec<(String, String)> = Vec::new();
    let now = |p: &str, moved: &[(String, String)]| -> String {
        let mut p = p.to_string();
        for (from, to) in moved {
            if &p == from {
                p = to.clone();
            } else if let Some(rest) = p.strip_prefix(&format!("{from}/")) {
                p = format!("{to}/{rest}");
            }
        }
        p
    };
    let mut folders: Vec<(&String, &Vec<Entry>)> =
        entries.iter().filter(|(_, lines)| lines.iter().any(|e| e.kind == Kind::Folder)).collect();
    folders.sort_by_key(|(rel, _)| rel.matches('/').count());
    for (rel, lines) in folders {
        let current = now(rel, &moved);
        let names = components(&current).unwrap_or_default();
        let Some((last, above)) = names.split_last() else { continue };
        let Some(parent) = walk(root, above) else { continue };
        let aside = removal_name(last);
        let ours = |name: &str| {
            rustix::fs::statat(&parent, name, AtFlags::SYMLINK_NOFOLLOW)
                .ok()
                .filter(|s| recorded(lines, s).is_some_and(|e| e.kind == Kind::Folder) && !is_input(s))
        };
        let moved_to = if ours(last).is_some() {
            rustix::fs::renameat(&parent, *last, &parent, aside.as_str()).ok().map(|()| aside)
        } else if ours(&aside).is_some() {
            Some(aside)
        } else {
            None
        };
        if let Some(aside) = moved_to {
            let to = match current.rsplit_once('/') {
                Some((dir, _)) => format!("{dir}/{aside}"),
                None => aside,
            };
            moved.push((current, to));
        }
    }
    let mut ordered: Vec<(&Vec<Entry>, String)> =
        entries.values().map(|lines| (lines, now(&lines[0].path, &moved))).collect();
    ordered.sort_by_key(|(lines, p)| {
        (std::cmp::Reverse(p.matches('/').count()), lines.iter().all(|e| e.kind == Kind::Folder))
    });
    for (lines, current) in ordered {
        remove(&current, lines)?;
    }
    // a folder moved aside that keeps what the run did not make goes back to its place
    for (from, to) in moved.iter().rev() {
        let (Ok(f), Ok(t)) = (components(from), components(to)) else { continue };
        let (Some((from_last, above)), Some((to_last, _))) = (f.split_last(), t.split_last()) else { continue };
        if let Some(parent) = walk(root, above) {
            if rustix::fs::statat(&parent, *to_last, AtFlags::SYMLINK_NOFOLLOW).is_ok() {
                let _ = rustix::fs::renameat(&parent, *to_last, &parent, *from_last);
            }
        }
    }
    Ok(Vec::new())
}
