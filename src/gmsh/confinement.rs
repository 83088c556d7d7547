//! The confinement Gmsh runs in, by the Linux kernel's Landlock (no root needed) and resource
//! limits.
//!
//! A thread of geoslip's own restricts itself with a Landlock ruleset, then starts Gmsh, which
//! inherits the restriction and can never drop it (no_new_privs is set with it):
//! - files: read (not execute) under the system's program and library folders (`/usr`, `/lib*`,
//!   `/bin`, `/sbin`), the loader's cache in `/etc`, and the script's own folder; read and write
//!   `/dev/null`; read, write, create and remove only in the scratch folder; execute only the Gmsh
//!   program and the ELF loader, so a shell command of the script cannot start;
//! - network: no TCP bind or connect; no abstract Unix socket or signal outside the sandbox;
//! - the environment is emptied but for HOME, XDG_CONFIG_HOME and TMPDIR (all the scratch folder),
//!   PATH and LANG;
//! - resource limits (set in the child before Gmsh starts, `native::child_limits`): address
//!   space, file size, CPU time, no core file, and the child dies with geoslip;
//! - the wall time: the child is killed when it passes `wall_seconds`.
//!
//! The rules need Landlock ABI 6 (Linux 6.12 and later). On a kernel that cannot enforce every one
//! of them the run is refused, and the message says why and what to do.

use landlock::{
    Access, AccessFs, AccessNet, PathBeneath, PathFd, Ruleset, RulesetAttr, RulesetCreatedAttr, RulesetStatus, Scope,
    ABI,
};
use std::io::{Read, Seek};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Bounds on a confined program.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    pub memory_bytes: u64,
    pub file_bytes: u64,
    pub wall_seconds: f64,
}

/// What the program printed and how it ended.
#[derive(Debug)]
pub struct Output {
    pub status: ExitStatus,
    pub stdout: Vec<u8>,
    pub stderr: Vec<u8>,
}

/// Why a confined program did not run to its end.
#[derive(Debug, thiserror::Error)]
pub enum ConfineError {
    #[error(
        "this kernel cannot confine Gmsh ({0}), and a .geo script is a program that could then read, write or run \
         anything geoslip can; mesh it yourself and point mesh.file at the .msh, or, if you trust the script, pass \
         --trust-geo"
    )]
    Unconfinable(String),
    #[error("gmsh could not be started: {0}")]
    Start(std::io::Error),
    #[error("gmsh was stopped after {0:.0} s (--gmsh-time-limit): the script takes longer than allowed")]
    TimedOut(f64),
}

/// The ABI whose rules the confinement needs (scopes came with ABI 6).
const ABI_NEEDED: ABI = ABI::V6;

/// The absolute, resolved path of a program: as given when it names a path, else the first match
/// on the PATH; a regular file.
pub fn find_program(name: &Path) -> Option<PathBuf> {
    let candidates: Vec<PathBuf> = if name.components().count() > 1 {
        vec![name.to_path_buf()]
    } else {
        std::env::var_os("PATH")
            .map(|p| std::env::split_paths(&p).map(|dir| dir.join(name)).collect())
            .unwrap_or_default()
    };
    candidates.into_iter().filter_map(|p| p.canonicalize().ok()).find(|p| p.is_file())
}

/// The ELF loaders a dynamically linked program may name (the kernel opens the one it names for
/// execution, so it needs the execute right too).
const LOADERS: &[&str] = &[
    "/lib64/ld-linux-x86-64.so.2",
    "/lib/ld-linux-aarch64.so.1",
    "/lib/ld-linux-armhf.so.3",
    "/lib/ld-linux.so.2",
    "/lib/ld64.so.2",
    "/lib/ld-linux-riscv64-lp64d.so.1",
];

/// Folders a program reads its libraries and shared data from.
const SYSTEM_FOLDERS: &[&str] = &["/usr", "/lib", "/lib64", "/bin", "/sbin"];

/// Files of /etc the loader reads.
const LOADER_FILES: &[&str] = &["/etc/ld.so.cache", "/etc/ld.so.conf", "/etc/ld.so.conf.d"];

fn ruleset(program: &Path, readable: &Path, scratch: &Path) -> Result<landlock::RulesetCreated, String> {
    let abi = ABI_NEEDED;
    let all = AccessFs::from_all(abi);
    let read = AccessFs::from_read(abi) & !AccessFs::Execute;
    let run = AccessFs::Execute | AccessFs::ReadFile;
    let null = AccessFs::ReadFile | AccessFs::WriteFile;
    let fail = |e: &dyn std::fmt::Display| e.to_string();
    let mut rules: Vec<(PathBuf, landlock::BitFlags<AccessFs>)> = Vec::new();
    for folder in SYSTEM_FOLDERS.iter().chain(LOADER_FILES) {
        if Path::new(folder).exists() {
            rules.push((folder.into(), if Path::new(folder).is_dir() { read } else { AccessFs::ReadFile.into() }));
        }
    }
    rules.push((readable.to_path_buf(), read));
    rules.push((scratch.to_path_buf(), all));
    rules.push(("/dev/null".into(), null));
    rules.push((program.to_path_buf(), run));
    for loader in LOADERS {
        if Path::new(loader).exists() {
            rules.push((loader.into(), run));
        }
    }
    let mut created = Ruleset::default()
        .handle_access(all)
        .map_err(|e| fail(&e))?
        .handle_access(AccessNet::from_all(abi))
        .map_err(|e| fail(&e))?
        .scope(Scope::from_all(abi))
        .map_err(|e| fail(&e))?
        .create()
        .map_err(|e| fail(&e))?;
    for (path, access) in rules {
        let fd = PathFd::new(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        created = created.add_rule(PathBeneath::new(fd, access)).map_err(|e| fail(&e))?;
    }
    Ok(created)
}

/// Run `command` (whose program is `program`), confined when `confine`, within `limits`; its
/// output goes through files in `scratch`.
///
/// # Errors
/// [`ConfineError`]: the kernel cannot confine it, it cannot start, or it ran out of time.
pub fn run(
    mut command: Command,
    program: &Path,
    readable: &Path,
    scratch: &Path,
    limits: Limits,
    confine: bool,
) -> Result<Output, ConfineError> {
    // the program gets copies of the handles, and its output is read back through ours: a name in
    // the scratch folder could have been made a link to anywhere by then
    let mut stdout = tempfile::tempfile_in(scratch).map_err(ConfineError::Start)?;
    let mut stderr = tempfile::tempfile_in(scratch).map_err(ConfineError::Start)?;
    let open = |f: &std::fs::File| f.try_clone().map_err(ConfineError::Start);
    command
        .env_clear()
        .env("HOME", scratch)
        .env("XDG_CONFIG_HOME", scratch)
        .env("TMPDIR", scratch)
        .env("PATH", "/usr/bin:/bin")
        .env("LANG", "C")
        .stdin(Stdio::null())
        .stdout(open(&stdout)?)
        .stderr(open(&stderr)?);
    crate::native::child_limits::set(&mut command, limits.memory_bytes, limits.file_bytes, limits.wall_seconds);
    let (program, readable, scratch_owned) = (program.to_path_buf(), readable.to_path_buf(), scratch.to_path_buf());
    // the restriction holds for this thread and what it starts, and ends with it
    let status = std::thread::spawn(move || -> Result<ExitStatus, ConfineError> {
        if confine {
            let created = ruleset(&program, &readable, &scratch_owned).map_err(ConfineError::Unconfinable)?;
            let status = created.restrict_self().map_err(|e| ConfineError::Unconfinable(e.to_string()))?;
            if status.ruleset != RulesetStatus::FullyEnforced || !status.no_new_privs {
                return Err(ConfineError::Unconfinable(format!(
                    "Landlock {:?}; geoslip needs Landlock ABI 6, Linux 6.12 or later, enabled at boot",
                    status.landlock
                )));
            }
        }
        let mut child = command.spawn().map_err(ConfineError::Start)?;
        let start = Instant::now();
        loop {
            if let Some(status) = child.try_wait().map_err(ConfineError::Start)? {
                return Ok(status);
            }
            if start.elapsed().as_secs_f64() > limits.wall_seconds {
                let _ = child.kill();
                let _ = child.wait();
                return Err(ConfineError::TimedOut(limits.wall_seconds));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    })
    .join()
    .unwrap_or_else(|_| Err(ConfineError::Start(std::io::Error::other("the thread that runs gmsh failed"))))?;
    // at most 1 MB of each: a message, not a log to keep
    let head = |f: &mut std::fs::File| {
        let mut bytes = Vec::new();
        if f.seek(std::io::SeekFrom::Start(0)).is_ok() {
            let _ = f.by_ref().take(1 << 20).read_to_end(&mut bytes);
        }
        bytes
    };
    Ok(Output { status, stdout: head(&mut stdout), stderr: head(&mut stderr) })
}
