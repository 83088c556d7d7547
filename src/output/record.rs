//! The record of what a run made in its output folder (`.geoslip-owned`): its lines, written by
//! `owned_folder.rs` and read by `record_removal.rs`, and the small helpers both use.

use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::path::{Component, Path};

/// The record of what a run made in its folder.
pub const RECORD: &str = ".geoslip-owned";

/// The largest record read back: far more lines than any run writes.
pub const LARGEST_RECORD: u64 = 256 << 20;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum Kind {
    File,
    Folder,
}

/// One line of the record. A path may have several lines (a name given to a new object, a file
/// replaced): an object at that path is the run's when any of them is it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(super) struct Entry {
    pub(super) path: String,
    pub(super) kind: Kind,
    /// A temporary name (`.partial-<process>-<time>-…`) noted before it is made, so that a run
    /// killed between making it and noting it leaves nothing the next run does not remove.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub(super) pending: bool,
    #[serde(default)]
    pub(super) dev: u64,
    #[serde(default)]
    pub(super) ino: u64,
    /// A whole file's size and modification time (ns) once written: it is removed only while both
    /// are unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) size: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) mtime_ns: Option<i128>,
}

pub(super) fn io(e: rustix::io::Errno) -> std::io::Error {
    std::io::Error::from(e)
}

/// The components of a relative path inside the folder: plain names only.
pub(super) fn components(rel: &str) -> Result<Vec<&str>, String> {
    let mut names = Vec::new();
    for c in Path::new(rel).components() {
        match c {
            Component::Normal(n) => names.push(n.to_str().ok_or_else(|| format!("`{rel}` is not UTF-8"))?),
            _ => return Err(format!("`{rel}` is not a plain path inside the output folder")),
        }
    }
    if names.is_empty() {
        return Err("an empty path".into());
    }
    Ok(names)
}

pub(super) fn mtime_ns(stat: &rustix::fs::Stat) -> i128 {
    i128::from(stat.st_mtime) * 1_000_000_000 + i128::from(stat.st_mtime_nsec)
}

pub(super) fn refusal(path: &Path, why: &str) -> Error {
    Error::Write { path: path.to_path_buf(), source: std::io::Error::other(why.to_string()) }
}
