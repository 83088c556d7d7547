//! Meshing a `.geo` script with Debian's `gmsh`, confined.
//!
//! A `.geo` file is a program: Gmsh's language can run shell commands, include any file as more
//! script, merge a `<script>.opt` file found beside it, write files through plugins, and loop for
//! ever. A model may come from anyone, so Gmsh runs where none of that can do harm, whatever the
//! script says (see [`super::confinement`]):
//! - it reads the script's folder and the system's programs and libraries, nothing else;
//! - it writes only a fresh scratch folder, which is also its HOME (its preference files go there);
//! - it executes no program but itself, and reaches no network;
//! - it has a bound on its memory (the run's `--memory-limit`), on the size of any file it writes,
//!   on its CPU time, and on its wall time (`--gmsh-time-limit`), after which it is killed.
//!
//! The scanner of [`crate::geo_script`] still reads the script first and refuses, with the line,
//! a command that runs programs or touches files: a readable refusal, not the guard. With
//! `--trust-geo` neither the scanner nor the confinement applies. Where the kernel cannot confine
//! (no Landlock, or one too old for the rules above), a `.geo` is meshed only with `--trust-geo`.

use super::confinement::{self, Limits};
use super::types::{err, GmshError, GmshMesh};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A mesh that Gmsh made from a `.geo` file for this run.
#[derive(Debug, Clone)]
pub struct GeneratedMesh {
    pub geometry: PathBuf,
    /// `gmsh --version`.
    pub gmsh_version: String,
    /// The `.msh` file's bytes (format 4.1), kept so that the run can save the mesh it used.
    pub msh: Vec<u8>,
}

/// Refuse a `.geo` script that runs programs or touches files (see `geo_script`).
///
/// # Errors
/// The first such command's file and line, with up to five of them listed.
pub fn refuse_script_actions(geometry: &Path) -> Result<(), GmshError> {
    let actions = crate::geo_script::actions(geometry);
    let Some(first) = actions.first() else { return Ok(()) };
    let list: Vec<String> =
        actions.iter().take(5).map(|a| format!("{}:{}: {}", a.file.display(), a.line, a.what)).collect();
    Err(err(
        &first.file,
        Some(first.line),
        format!(
            "the mesh script does what geoslip does not run unasked (a .geo file is a program):\n    {}\n\
             Read the script; if you trust it, pass --trust-geo, or mesh it yourself and point mesh.file at the .msh",
            list.join("\n    ")
        ),
    ))
}

/// How Gmsh may run.
#[derive(Debug, Clone, Copy)]
pub struct MeshingOptions {
    /// `--trust-geo`: no scanner, no confinement.
    pub trust_script: bool,
    /// The run's memory limit, MB (`None`: what the machine has available).
    pub memory_limit_mb: Option<f64>,
    /// `--gmsh-time-limit`, seconds of wall time.
    pub time_limit_s: f64,
}

/// Mesh a `.geo` file in 2-D with `gmsh` (format 4.1), confined unless `options.trust_script`, and
/// read the result.
///
/// # Errors
/// A [`GmshError`] when the script is refused, when the kernel cannot confine Gmsh, or when `gmsh`
/// is not installed, fails, is stopped at a limit, or writes a mesh that cannot be read.
pub fn mesh_geometry(geometry: &Path, options: MeshingOptions) -> Result<(GmshMesh, GeneratedMesh), GmshError> {
    if !options.trust_script {
        refuse_script_actions(geometry)?;
    }
    let gmsh = std::env::var_os("GEOSLIP_GMSH").unwrap_or_else(|| "gmsh".into());
    let program = confinement::find_program(Path::new(&gmsh)).ok_or_else(|| {
        err(
            geometry,
            None,
            format!(
                "meshing a .geo file needs Gmsh, and `{}` is not a program on the PATH; install it (Debian: apt-get \
                 install gmsh) or point mesh.file at a .msh file",
                Path::new(&gmsh).display()
            ),
        )
    })?;
    let folder = geometry.canonicalize().map_err(|e| err(geometry, None, format!("cannot find the script: {e}")))?;
    let script_folder = folder.parent().unwrap_or(Path::new("/")).to_path_buf();
    let scratch = tempfile::tempdir().map_err(|e| err(geometry, None, format!("cannot make a scratch folder: {e}")))?;
    let memory = crate::input_file::SizeLimit::of_memory(options.memory_limit_mb);
    let limits = Limits {
        memory_bytes: memory.bytes,
        // a mesh and Gmsh's log: well within what the run may hold in memory
        file_bytes: memory.bytes,
        wall_seconds: options.time_limit_s,
    };
    let run = |args: &[&std::ffi::OsStr]| {
        let mut command = Command::new(&program);
        command.args(args).current_dir(scratch.path());
        confinement::run(command, &program, &script_folder, scratch.path(), limits, !options.trust_script)
    };
    let version = run(&["--version".as_ref()]).map_err(|e| err(geometry, None, e.to_string()))?;
    let version_text = [&version.stdout, &version.stderr]
        .iter()
        .map(|s| String::from_utf8_lossy(s).trim().to_string())
        .find(|s| !s.is_empty())
        .unwrap_or_default();
    let out = scratch.path().join("mesh.msh");
    let meshed = run(&[
        folder.as_os_str(),
        "-2".as_ref(),
        "-format".as_ref(),
        "msh41".as_ref(),
        "-v".as_ref(),
        "2".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ])
    .map_err(|e| err(geometry, None, e.to_string()))?;
    if !meshed.status.success() || !out.is_file() {
        let log = format!("{}{}", String::from_utf8_lossy(&meshed.stdout), String::from_utf8_lossy(&meshed.stderr));
        let tail: Vec<&str> = log.lines().rev().take(8).collect::<Vec<_>>().into_iter().rev().collect();
        return Err(err(geometry, None, format!("gmsh could not mesh the geometry:\n    {}", tail.join("\n    "))));
    }
    let bytes = crate::input_file::read_not_linked(&out, memory)
        .map_err(|e| err(geometry, None, format!("cannot read gmsh's output: {e}")))?;
    super::read::check_declared_size(
        geometry,
        &bytes,
        options.memory_limit_mb.or_else(crate::memory::available_memory_mb),
    )?;
    let mut mesh = GmshMesh::from_bytes(&out, &bytes)?;
    mesh.path = geometry.to_path_buf();
    Ok((mesh, GeneratedMesh { geometry: geometry.to_path_buf(), gmsh_version: version_text, msh: bytes }))
}
