//! The output folder as geoslip owns it: one handle on the folder, through which every file and
//! folder of a run is made, replaced or removed, never following a link, and a record of what was
//! made (`.geoslip-owned`) that the next run into the folder reads to remove exactly that.
//!
//! - **Never through a link.** The folder given (`--out`) is opened once, as the user named it. Below
//!   it, each component of a path is opened with `O_NOFOLLOW` from the one before (`openat`): a
//!   link anywhere below `--out` on a path geoslip writes is refused with its path, never followed.
//! - **Write only what is ours.** A name geoslip must write that is taken by a file or folder it did
//!   not make, or by an input of the run (the model file, its mesh), is refused with the path.
//! - **Delete only what we wrote.** Each file and folder made is recorded (`.geoslip-owned`, one
//!   JSON object a line: its path, device and inode, and for a whole file its size and time) before
//!   it takes its name. The next run removes each recorded entry that is still the same object
//!   (same device, inode and kind; for a file, the same size and time) and is no input of that run,
//!   deepest first, and leaves everything else. An earlier run's file that was changed since stops
//!   the next run before it writes anything, naming the file.
//! - **Whole or not at all.** A file is written under a temporary name (recorded too), synced, and
//!   renamed into place, so a killed run never leaves a truncated file under a result's name.
//!
//! Libraries that open files by name (HDF5) get `/proc/self/fd/<folder>/<name>` for a file made
//! here first: the folder is the one this handle holds, whatever happens to the names above it.

use super::folder::write_error;
pub use super::record::RECORD;
use super::record::{components, io, mtime_ns, refusal, Entry, Kind};
use crate::error::Error;
use rustix::fs::{AtFlags, FileType, Mode, OFlags};
use std::collections::{HashMap, HashSet};
use std::io::Write;
use std::os::fd::{AsFd, AsRawFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A handle on an output folder (cheap to clone; every clone is the same handle).
#[derive(Clone)]
pub struct OwnedFolder(Arc<Inner>);

struct Inner {
    /// The folder as the user named it, for messages.
    path: PathBuf,
    root: OwnedFd,
    /// Folders below the root opened so far, by relative path.
    folders: Mutex<HashMap<String, Arc<OwnedFd>>>,
    record: Mutex<std::fs::File>,
    /// What this run made, by relative path.
    made: Mutex<HashSet<String>>,
    /// (device, inode) of the run's input files.
    inputs: Vec<(u64, u64)>,
}

impl OwnedFolder {
    /// Open (making it if need be) the folder `path` for a run whose inputs are `inputs`, and
    /// remove what the earlier run recorded there and left unchanged.
    ///
    /// # Errors
    /// [`Error::Write`]: the folder cannot be made or opened, its record is a link, or a file the
    /// earlier run wrote was changed since (named).
    pub fn open(path: &Path, inputs: &[&Path]) -> Result<OwnedFolder, Error> {
        std::fs::create_dir_all(path).map_err(write_error(path))?;
        let root = rustix::fs::open(path, OFlags::DIRECTORY | OFlags::RDONLY | OFlags::CLOEXEC, Mode::empty())
            .map_err(|e| Error::Write { path: path.to_path_buf(), source: io(e) })?;
        let inputs = inputs
            .iter()
            .filter_map(|p| std::fs::metadata(p).ok())
            .map(|m| (std::os::unix::fs::MetadataExt::dev(&m), std::os::unix::fs::MetadataExt::ino(&m)))
            .collect::<Vec<_>>();
        let changed = super::record_removal::remove_recorded(&root, path, &inputs)?;
        if let Some(first) = changed.first() {
            return Err(Error::Write {
                path: path.join(first),
                source: std::io::Error::other(format!(
                    "an earlier run into this folder wrote it and it has changed since ({} such file{}): geoslip \
                     replaces only what it wrote and nobody changed; move it, or choose another --out",
                    changed.len(),
                    if changed.len() == 1 { "" } else { "s" }
                )),
            });
        }
        // the new record replaces the old one (a link or a foreign file under its name is refused)
        match rustix::fs::statat(&root, RECORD, AtFlags::SYMLINK_NOFOLLOW) {
            Ok(stat) if FileType::from_raw_mode(stat.st_mode) != FileType::RegularFile => {
                return Err(refusal(&path.join(RECORD), "it is not a file geoslip wrote (a link or a folder)"));
            }
            _ => {}
        }
        let record = rustix::fs::openat(
            &root,
            RECORD,
            OFlags::WRONLY | OFlags::CREATE | OFlags::TRUNC | OFlags::NOFOLLOW | OFlags::CLOEXEC | OFlags::APPEND,
            Mode::from_raw_mode(0o666),
        )
        .map_err(|e| Error::Write { path: path.join(RECORD), source: io(e) })?;
        Ok(OwnedFolder(Arc::new(Inner {
            path: path.to_path_buf(),
            root,
            folders: Mutex::new(HashMap::new()),
            record: Mutex::new(std::fs::File::from(record)),
            made: Mutex::new(HashSet::new()),
            inputs,
        })))
    }

    /// The folder as the user named it.
    pub fn path(&self) -> &Path {
        &self.0.path
    }

    /// A folder below this one, made (and recorded) here, as an output folder of its own for a run
    /// whose inputs are `inputs` (a run of a series): its own record removes its own files.
    ///
    /// # Errors
    /// As [`OwnedFolder::open`]; a link or a foreign file in its place.
    pub fn subfolder(&self, name: &str, inputs: &[&Path]) -> Result<OwnedFolder, Error> {
        let fd = self.folder(name)?;
        // opened through this handle's folder, whatever the names above it are now
        let via = PathBuf::from(format!("/proc/self/fd/{}", fd.as_raw_fd()));
        let mut sub = OwnedFolder::open(&via, inputs)?;
        let inner = Arc::get_mut(&mut sub.0).expect("a new handle has one owner");
        inner.path = self.0.path.join(name);
        Ok(sub)
    }

    fn fail<'a>(&'a self, rel: &'a str) -> impl Fn(std::io::Error) -> Error + 'a {
        move |source| Error::Write { path: self.0.path.join(rel), source }
    }

    /// Append `entry` to the record.
    fn note(&self, entry: &Entry) -> Result<(), Error> {
        let mut line = serde_json::to_vec(entry).unwrap_or_default();
        line.push(b'\n');
        let mut record = self.0.record.lock().unwrap_or_else(|p| p.into_inner());
        record.write_all(&line).map_err(write_error(&self.0.path.join(RECORD)))
    }

    fn note_pending(&self, rel: &str, kind: Kind) -> Result<(), Error> {
        self.note(&Entry { path: rel.to_string(), kind, pending: true, dev: 0, ino: 0, size: None, mtime_ns: None })
    }

    fn note_stat(&self, rel: &str, kind: Kind, stat: &rustix::fs::Stat, whole: bool) -> Result<(), Error> {
        self.note(&Entry {
            path: rel.to_string(),
            kind,
            pending: false,
            dev: stat.st_dev,
            ino: stat.st_ino,
            size: whole.then_some(stat.st_size as u64),
            mtime_ns: whole.then(|| mtime_ns(stat)),
        })
    }

    /// The folder `rel` (made, and recorded, where missing), opened without following a link.
    fn folder(&self, rel: &str) -> Result<Arc<OwnedFd>, Error> {
        if let Some(fd) = self.0.folders.lock().unwrap_or_else(|p| p.into_inner()).get(rel) {
            return Ok(fd.clone());
        }
        let names = components(rel).map_err(|m| self.fail(rel)(std::io::Error::other(m)))?;
        let mut at: Option<Arc<OwnedFd>> = None;
        let mut walked = String::new();
        for name in names {
            if !walked.is_empty() {
                walked.push('/');
            }
            walked.push_str(name);
            let cached = self.0.folders.lock().unwrap_or_else(|p| p.into_inner()).get(&walked).cloned();
            let fd = match cached {
                Some(fd) => fd,
                None => {
                    let parent: &OwnedFd = at.as_deref().unwrap_or(&self.0.root);
                    let fd = Arc::new(self.open_or_make_folder(parent, name, &walked)?);
                    self.0.folders.lock().unwrap_or_else(|p| p.into_inner()).insert(walked.clone(), fd.clone());
                    fd
                }
            };
            at = Some(fd);
        }
        Ok(at.expect("at least one component"))
    }

    fn open_or_make_folder(&self, parent: &OwnedFd, name: &str, rel: &str) -> Result<OwnedFd, Error> {
        match rustix::fs::statat(parent, name, AtFlags::SYMLINK_NOFOLLOW) {
            Ok(stat) => {
                let kind = FileType::from_raw_mode(stat.st_mode);
                if kind == FileType::Symlink {
                    return Err(refusal(
                        &self.0.path.join(rel),
                        "it is a link, and geoslip does not write through links",
                    ));
                }
                if kind != FileType::Directory {
                    return Err(refusal(
                        &self.0.path.join(rel),
                        "geoslip must make a folder there and a file has the name",
                    ));
                }
            }
            Err(rustix::io::Errno::NOENT) => {
                rustix::fs::mkdirat(parent, name, Mode::from_raw_mode(0o777)).map_err(|e| self.fail(rel)(io(e)))?;
                let stat =
                    rustix::fs::statat(parent, name, AtFlags::SYMLINK_NOFOLLOW).map_err(|e| self.fail(rel)(io(e)))?;
                self.note_stat(rel, Kind::Folder, &stat, false)?;
                self.0.made.lock().unwrap_or_else(|p| p.into_inner()).insert(rel.to_string());
            }
            Err(e) => return Err(self.fail(rel)(io(e))),
        }
        rustix::fs::openat(
            parent,
            name,
            OFlags::DIRECTORY | OFlags::RDONLY | OFlags::NOFOLLOW | OFlags::CLOEXEC,
            Mode::empty(),
        )
        .map_err(|e| self.fail(rel)(io(e)))
    }

    /// The folder holding `rel` and the last name of `rel`.
    fn parent_of<'a>(&self, rel: &'a str) -> Result<(Option<Arc<OwnedFd>>, &'a str), Error> {
        match rel.rsplit_once('/') {
            Some((dir, name)) => Ok((Some(self.folder(dir)?), name)),
            None => {
                components(rel).map_err(|m| self.fail(rel)(std::io::Error::other(m)))?;
                Ok((None, rel))
            }
        }
    }

    /// Check that `name` in `parent` may be replaced: absent, or a file this run made that is no
    /// input.
    fn check_replaceable(&self, parent: &OwnedFd, name: &str, rel: &str, kind: Kind) -> Result<(), Error> {
        let stat = match rustix::fs::statat(parent, name, AtFlags::SYMLINK_NOFOLLOW) {
            Ok(stat) => stat,
            Err(rustix::io::Errno::NOENT) => return Ok(()),
            Err(e) => return Err(self.fail(rel)(io(e))),
        };
        let path = self.0.path.join(rel);
        let found = FileType::from_raw_mode(stat.st_mode);
        if found == FileType::Symlink {
            return Err(refusal(&path, "it is a link, and geoslip does not write through links"));
        }
        if self.0.inputs.contains(&(stat.st_dev, stat.st_ino)) {
            return Err(refusal(
                &path,
                "it is an input of this run, which geoslip never replaces; choose another --out",
            ));
        }
        let expected = if kind == Kind::File { FileType::RegularFile } else { FileType::Directory };
        if found != expected || !self.0.made.lock().unwrap_or_else(|p| p.into_inner()).contains(rel) {
            return Err(refusal(
                &path,
                "geoslip must write this name and it is taken by something geoslip did not write; move it, or choose another --out",
            ));
        }
        Ok(())
    }

    /// Write `bytes` to the file `rel` (a path inside the folder), whole or not at all.
    ///
    /// # Errors
    /// [`Error::Write`] naming the file: a link on the way, a name taken by what geoslip did not
    /// write, or an I/O error.
    pub fn write(&self, rel: &str, bytes: &[u8]) -> Result<(), Error> {
        let (parent, name) = self.parent_of(rel)?;
        let parent: &OwnedFd = parent.as_deref().unwrap_or(&self.0.root);
        self.check_replaceable(parent, name, rel, Kind::File)?;
        let temp = self.temporary(parent, name, rel)?;
        let (mut file, temp_name) = temp;
        let done = (|| {
            file.write_all(bytes)?;
            file.sync_all()
        })();
        if let Err(e) = done {
            let _ = rustix::fs::unlinkat(parent, temp_name.as_str(), AtFlags::empty());
            return Err(self.fail(rel)(e));
        }
        // noted under its name before it takes it: a run killed between the two leaves a file
        // the next run knows
        let stat = rustix::fs::fstat(file.as_fd()).map_err(|e| self.fail(rel)(io(e)))?;
        self.note_stat(rel, Kind::File, &stat, true)?;
        rustix::fs::renameat(parent, temp_name.as_str(), parent, name).map_err(|e| self.fail(rel)(io(e)))?;
        self.0.made.lock().unwrap_or_else(|p| p.into_inner()).insert(rel.to_string());
        Ok(())
    }

    /// A name for a temporary object beside `name` that no other run or user has.
    fn temporary_name(name: &str, attempt: u32) -> String {
        format!(".partial-{}-{}-{attempt}-{name}", std::process::id(), nanos())
    }

    /// A new temporary file beside `name`, recorded under the temporary name.
    fn temporary(&self, parent: &OwnedFd, name: &str, rel: &str) -> Result<(std::fs::File, String), Error> {
        for attempt in 0..64u32 {
            let temp_name = Self::temporary_name(name, attempt);
            let temp_rel = match rel.rsplit_once('/') {
                Some((dir, _)) => format!("{dir}/{temp_name}"),
                None => temp_name.clone(),
            };
            self.note_pending(&temp_rel, Kind::File)?;
            match rustix::fs::openat(
                parent,
                temp_name.as_str(),
                OFlags::WRONLY | OFlags::CREATE | OFlags::EXCL | OFlags::NOFOLLOW | OFlags::CLOEXEC,
                Mode::from_raw_mode(0o666),
            ) {
                Ok(fd) => return Ok((std::fs::File::from(fd), temp_name)),
                Err(rustix::io::Errno::EXIST) => continue,
                Err(e) => return Err(self.fail(rel)(io(e))),
            }
        }
        Err(self.fail(rel)(std::io::Error::other("no free temporary name")))
    }

    /// Make a new folder beside `rel` under a temporary name of its own (recorded), and return its
    /// path: a step's files are written there, then the folder is moved to `rel`
    /// ([`OwnedFolder::move_folder`]).
    ///
    /// # Errors
    /// As [`OwnedFolder::write`].
    pub fn temporary_folder(&self, rel: &str) -> Result<String, Error> {
        let (parent, name) = self.parent_of(rel)?;
        let parent: &OwnedFd = parent.as_deref().unwrap_or(&self.0.root);
        for attempt in 0..64u32 {
            let temp_name = Self::temporary_name(name, attempt);
            let temp_rel = match rel.rsplit_once('/') {
                Some((dir, _)) => format!("{dir}/{temp_name}"),
                None => temp_name.clone(),
            };
            self.note_pending(&temp_rel, Kind::Folder)?;
            match rustix::fs::mkdirat(parent, temp_name.as_str(), Mode::from_raw_mode(0o777)) {
                Ok(()) => {
                    self.0.made.lock().unwrap_or_else(|p| p.into_inner()).insert(temp_rel.clone());
                    return Ok(temp_rel);
                }
                Err(rustix::io::Errno::EXIST) => continue,
                Err(e) => return Err(self.fail(rel)(io(e))),
            }
        }
        Err(self.fail(rel)(std::io::Error::other("no free temporary name")))
    }

    /// Make the folder `rel` (and those above it), recorded, unless it is there already.
    ///
    /// # Errors
    /// As [`OwnedFolder::write`].
    pub fn make_folder(&self, rel: &str) -> Result<(), Error> {
        self.folder(rel).map(|_| ())
    }

    /// Make the file `rel` empty for a library that writes it by name, and return the name it
    /// is to use (through this handle's folder). [`OwnedFolder::record`] notes its size and time
    /// once the library is done with it.
    ///
    /// # Errors
    /// As [`OwnedFolder::write`].
    pub fn file_for_library(&self, rel: &str) -> Result<PathBuf, Error> {
        let (parent, name) = self.parent_of(rel)?;
        let parent_fd: &OwnedFd = parent.as_deref().unwrap_or(&self.0.root);
        self.check_replaceable(parent_fd, name, rel, Kind::File)?;
        if self.0.made.lock().unwrap_or_else(|p| p.into_inner()).contains(rel) {
            rustix::fs::unlinkat(parent_fd, name, AtFlags::empty()).map_err(|e| self.fail(rel)(io(e)))?;
        }
        let (file, temp_name) = self.temporary(parent_fd, name, rel)?;
        let stat = rustix::fs::fstat(file.as_fd()).map_err(|e| self.fail(rel)(io(e)))?;
        self.note_stat(rel, Kind::File, &stat, false)?;
        rustix::fs::renameat(parent_fd, temp_name.as_str(), parent_fd, name).map_err(|e| self.fail(rel)(io(e)))?;
        self.0.made.lock().unwrap_or_else(|p| p.into_inner()).insert(rel.to_string());
        let folder_fd = parent_fd.as_raw_fd();
        Ok(PathBuf::from(format!("/proc/self/fd/{folder_fd}/{name}")))
    }

    /// Note the size and time of `rel`, a file made by [`OwnedFolder::file_for_library`] that its
    /// library has finished with, so that the next run removes it only while they are unchanged.
    ///
    /// # Errors
    /// As [`OwnedFolder::write`].
    pub fn record(&self, rel: &str) -> Result<(), Error> {
        let (parent, name) = self.parent_of(rel)?;
        let parent: &OwnedFd = parent.as_deref().unwrap_or(&self.0.root);
        let stat = rustix::fs::statat(parent, name, AtFlags::SYMLINK_NOFOLLOW).map_err(|e| self.fail(rel)(io(e)))?;
        self.note_stat(rel, Kind::File, &stat, true)
    }

    /// Whether this run has made `rel`.
    pub fn made(&self, rel: &str) -> bool {
        self.0.made.lock().unwrap_or_else(|p| p.into_inner()).contains(rel)
    }

    /// Move the folder `from`, made by this run, to `to` (absent, or a folder this run made, which
    /// is removed first): a step's folder appears whole or not at all.
    ///
    /// # Errors
    /// As [`OwnedFolder::write`].
    pub fn move_folder(&self, from: &str, to: &str) -> Result<(), Error> {
        let (from_parent, from_name) = self.parent_of(from)?;
        let (to_parent, to_name) = self.parent_of(to)?;
        let from_fd: &OwnedFd = from_parent.as_deref().unwrap_or(&self.0.root);
        let to_fd: &OwnedFd = to_parent.as_deref().unwrap_or(&self.0.root);
        if !self.made(from) {
            return Err(refusal(&self.0.path.join(from), "geoslip moves only folders it made"));
        }
        self.check_replaceable(to_fd, to_name, to, Kind::Folder)?;
        if self.made(to) {
            self.remove_made(to)?;
        }
        // the folder and what it holds are noted under their new names before the move
        let prefix = format!("{from}/");
        let moved: Vec<String> = {
            let made = self.0.made.lock().unwrap_or_else(|p| p.into_inner());
            made.iter().filter(|p| p.starts_with(&prefix)).cloned().collect()
        };
        let stat =
            rustix::fs::statat(from_fd, from_name, AtFlags::SYMLINK_NOFOLLOW).map_err(|e| self.fail(from)(io(e)))?;
        self.note_stat(to, Kind::Folder, &stat, false)?;
        let mut renamed = Vec::new();
        for old in moved {
            let new = format!("{to}/{}", &old[prefix.len()..]);
            let (p, n) = self.parent_of(&old)?;
            let p: &OwnedFd = p.as_deref().unwrap_or(&self.0.root);
            if let Ok(stat) = rustix::fs::statat(p, n, AtFlags::SYMLINK_NOFOLLOW) {
                let kind = if FileType::from_raw_mode(stat.st_mode) == FileType::Directory {
                    Kind::Folder
                } else {
                    Kind::File
                };
                self.note_stat(&new, kind, &stat, kind == Kind::File)?;
            }
            renamed.push((old, new));
        }
        rustix::fs::renameat(from_fd, from_name, to_fd, to_name).map_err(|e| self.fail(to)(io(e)))?;
        let mut folders = self.0.folders.lock().unwrap_or_else(|p| p.into_inner());
        folders.retain(|k, _| k != from && !k.starts_with(&prefix));
        drop(folders);
        let mut made = self.0.made.lock().unwrap_or_else(|p| p.into_inner());
        made.remove(from);
        made.insert(to.to_string());
        for (old, new) in renamed {
            made.remove(&old);
            made.insert(new);
        }
        Ok(())
    }

    /// Remove `rel` (a file or folder this run made, with what this run made in it).
    fn remove_made(&self, rel: &str) -> Result<(), Error> {
        let prefix = format!("{rel}/");
        let mut inside: Vec<String> = {
            let made = self.0.made.lock().unwrap_or_else(|p| p.into_inner());
            made.iter().filter(|p| p.starts_with(&prefix)).cloned().collect()
        };
        inside.sort_by_key(|p| std::cmp::Reverse(p.matches('/').count()));
        inside.push(rel.to_string());
        for path in inside {
            let (p, n) = self.parent_of(&path)?;
            let p: &OwnedFd = p.as_deref().unwrap_or(&self.0.root);
            let is_dir = rustix::fs::statat(p, n, AtFlags::SYMLINK_NOFOLLOW)
                .is_ok_and(|s| FileType::from_raw_mode(s.st_mode) == FileType::Directory);
            let flags = if is_dir { AtFlags::REMOVEDIR } else { AtFlags::empty() };
            match rustix::fs::unlinkat(p, n, flags) {
                Ok(()) | Err(rustix::io::Errno::NOENT) => {}
                Err(e) => return Err(self.fail(&path)(io(e))),
            }
            self.0.made.lock().unwrap_or_else(|p| p.into_inner()).remove(&path);
            self.0.folders.lock().unwrap_or_else(|p| p.into_inner()).remove(&path);
        }
        Ok(())
    }
}

fn nanos() -> u32 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos())
}
