//! The output folder as a place to write into safely: names from the model made into path
//! components that stay inside it, an earlier run's results cleared (and nothing else), and every
//! file written whole or not at all (a temporary file, synced, renamed into place).

use crate::error::Error;
use std::io::Write;
use std::path::Path;

/// A name from the model (a stage, a series run) as one component of a path inside the output
/// folder: ASCII letters, digits, `-` and `_` kept, anything else (`/`, `.`, `\\`, spaces) made `-`,
/// at most 100 characters; never empty, never `.` or `..`, never absolute.
pub fn path_component(name: &str) -> String {
    let safe: String = name
        .chars()
        .take(100)
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' })
        .collect();
    if safe.is_empty() {
        "-".to_string()
    } else {
        safe
    }
}

/// A run into a folder that holds an earlier run's results replaces them: what a run writes there
/// (the step folders, the ParaView and HDF5 files, the summary, history, report, mesh and plots) is removed
/// first, so that nothing of the earlier run (steps beyond this run's last, other stages) stays.
/// The folder counts as an earlier run's only when its `summary.json` says geoslip wrote it; other
/// files are left alone.
pub(super) fn clear_earlier_run(out: &Path) -> Result<(), Error> {
    let summary = out.join("summary.json");
    let written_by_geoslip = std::fs::read(&summary)
        .ok()
        .and_then(|bytes| serde_json::from_slice::<serde_json::Value>(&bytes).ok())
        .is_some_and(|v| v.get("geoslip_version").is_some());
    if !written_by_geoslip {
        return Ok(());
    }
    let Ok(entries) = std::fs::read_dir(out) else { return Ok(()) };
    let mut entries: Vec<std::fs::DirEntry> = entries.flatten().collect();
    // the indexes first: a run killed while clearing never leaves an .xdmf or .pvd that names
    // files already removed
    entries.sort_by_key(|e| !["results.xdmf", "results.pvd"].contains(&e.file_name().to_string_lossy().as_ref()));
    for entry in entries {
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = entry.path();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        let ours = if is_dir {
            is_run_folder(&name)
        } else {
            ["history.csv", "report.md", "results.pvd", "results.h5", "results.xdmf", "mesh.msh"]
                .contains(&name.as_str())
                || ((name.starts_with("pullout.") || name.starts_with("profiles-"))
                    && (name.ends_with(".png") || name.ends_with(".svg")))
        };
        match (ours, is_dir) {
            (true, true) => remove_folder(&path)?,
            (true, false) => std::fs::remove_file(&path).map_err(write_error(&path))?,
            _ => {}
        }
    }
    // last: until it goes, a run killed while clearing leaves a folder the next run still
    // recognises as an earlier run's
    std::fs::remove_file(&summary).map_err(write_error(&summary))
}

/// Remove a folder so that a run killed on the way never leaves it half emptied under its own
/// name: it is renamed to a `.partial-*` name beside it first (which the next run removes, see
/// [`remove_partial_files`]), then removed.
pub(super) fn remove_folder(path: &Path) -> Result<(), Error> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let doomed = path.with_file_name(format!(".partial-removed-{name}"));
    if doomed.exists() {
        std::fs::remove_dir_all(&doomed).map_err(write_error(&doomed))?;
    }
    std::fs::rename(path, &doomed).map_err(write_error(path))?;
    std::fs::remove_dir_all(&doomed).map_err(write_error(&doomed))
}

/// The folder of saved steps inside a results folder (`checkpoints.rs`).
pub const CHECKPOINT_FOLDER: &str = "restart";

/// The folders a run writes in its output folder: one per stage (see `ResultWriter::step_dir`), the
/// ParaView parts (`vtk`) and the saved steps (`restart`).
fn is_run_folder(name: &str) -> bool {
    name.starts_with("stage-") || name == "vtk" || name == CHECKPOINT_FOLDER
}

/// The error of a failed write to `path`.
pub(super) fn write_error(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Write { path: path.to_path_buf(), source }
}

/// Remove what a run killed while writing left behind in `out`: the `.partial-*` files and step
/// folders that geoslip writes before renaming them into place, in `out` itself and in the folders
/// a run writes there (`stage-*`, `vtk`); nothing deeper, and nothing else.
pub(super) fn remove_partial_files(out: &Path) -> Result<(), Error> {
    let Ok(entries) = std::fs::read_dir(out) else { return Ok(()) };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = entry.path();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if name.starts_with(".partial-") {
            if is_dir {
                std::fs::remove_dir_all(&path).map_err(write_error(&path))?;
            } else {
                std::fs::remove_file(&path).map_err(write_error(&path))?;
            }
        } else if is_dir && is_run_folder(&name) {
            remove_partial_files(&path)?;
        }
    }
    Ok(())
}

/// Write `bytes` to `path` atomically (temporary file + rename).
///
/// # Errors
/// [`Error::Write`] naming the path.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let fail = |source: std::io::Error| Error::Write { path: path.to_path_buf(), source };
    std::fs::create_dir_all(dir).map_err(fail)?;
    // A result file is as readable as any file the user makes (0666 less the umask), not owner-only
    // as a temporary file is by default.
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let mut tmp = builder.prefix(".partial-").tempfile_in(dir).map_err(fail)?;
    tmp.write_all(bytes).map_err(fail)?;
    tmp.as_file().sync_all().map_err(fail)?;
    tmp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}

pub(super) fn csv_bytes(header: &[String], rows: impl Iterator<Item = Vec<String>>) -> Vec<u8> {
    let mut w = csv::Writer::from_writer(Vec::new());
    // Writing to memory cannot fail.
    w.write_record(header).expect("in-memory CSV");
    for r in rows {
        w.write_record(&r).expect("in-memory CSV");
    }
    w.into_inner().expect("in-memory CSV")
}

pub(super) fn num(v: f64) -> String {
    format!("{v:.10e}")
}
