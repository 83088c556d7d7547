//! The saved steps a run can continue from: `restart/stage-<k>-step-<nnnnn>.bin` in the results
//! folder, one per converged step of a loading stage, each the run's [`Checkpoint`] in bincode's
//! binary form (every number exactly as the run held it), deflated. Each is written as every result
//! file is ([`super::folder::write_atomically`]: a temporary file, synced, renamed into place), so a killed
//! run leaves no truncated saved step.
//!
//! `geoslip run MODEL --restart RESULTS --from STAGE:STEP` reads one back ([`read`]) and continues
//! from it when it fits the model ([`Checkpoint::fits`]).

use crate::analysis::Checkpoint;
use crate::error::Error;
use crate::model::Model;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

pub use super::folder::CHECKPOINT_FOLDER as FOLDER;

/// The largest saved step read back, MB (a file above it is refused before it is read).
const LARGEST_MB: u64 = 16 * 1024;

fn file_name(stage_index: usize, step: usize) -> String {
    format!("stage-{}-step-{step:05}.bin", stage_index + 1)
}

/// Write one saved step into `results/restart/`.
///
/// # Errors
/// [`Error::Write`] naming the file.
pub fn write(results: &Path, checkpoint: &Checkpoint) -> Result<(), Error> {
    let path = results.join(FOLDER).join(file_name(checkpoint.stage_index, checkpoint.step));
    let fail = |source: std::io::Error| Error::Write { path: path.clone(), source };
    let bytes = bincode::serialize(checkpoint).map_err(|e| fail(std::io::Error::other(e.to_string())))?;
    let mut deflate = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::fast());
    deflate.write_all(&bytes).map_err(fail)?;
    super::folder::write_atomically(&path, &deflate.finish().map_err(fail)?)
}

/// Where the run continues from: a stage (its name, or its number from 1) and a converged step of
/// it, as `STAGE:STEP`.
#[derive(Debug, Clone, PartialEq)]
pub struct From {
    pub stage: String,
    pub step: usize,
}

impl std::str::FromStr for From {
    type Err = String;
    fn from_str(s: &str) -> Result<From, String> {
        let (stage, step) = s.rsplit_once(':').ok_or_else(|| format!("\"{s}\": give STAGE:STEP, e.g. pull-out:12"))?;
        let step = step
            .parse::<usize>()
            .ok()
            .filter(|&k| k > 0)
            .ok_or_else(|| format!("\"{s}\": the step after ':' is a converged step's number, from 1"))?;
        if stage.is_empty() {
            return Err(format!("\"{s}\": name the stage before ':' (its name or its number from 1)"));
        }
        Ok(From { stage: stage.to_string(), step })
    }
}

/// Read the saved step `from` of the run whose results are in `results`, for a continuation on
/// `model` (whose stages name the stage), and check that it fits the model.
///
/// # Errors
/// [`Error::Restart`] naming the file or folder: no such stage, no such saved step (the saved ones
/// are listed), an unreadable file, or a model changed where the saved state depends on it.
pub fn read(results: &Path, from: &From, model: &Model) -> Result<Checkpoint, Error> {
    let folder = results.join(FOLDER);
    let refuse = |path: &Path, message: String| Error::Restart { path: path.to_path_buf(), message };
    let index = match from.stage.parse::<usize>() {
        Ok(k) if (1..=model.stages.len()).contains(&k) => k - 1,
        _ => model.stages.iter().position(|s| s.name == from.stage).ok_or_else(|| {
            let names: Vec<String> = model.stages.iter().map(|s| format!("\"{}\"", s.name)).collect();
            refuse(&folder, format!("the model has no stage \"{}\" (its stages: {})", from.stage, names.join(", ")))
        })?,
    };
    let path = folder.join(file_name(index, from.step));
    if !path.is_file() {
        return Err(refuse(
            &path,
            format!("no saved step {}:{} there ({})", from.stage, from.step, saved_steps(&folder)),
        ));
    }
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    if size > LARGEST_MB * 1024 * 1024 {
        return Err(refuse(
            &path,
            format!("the file is {} MB, above the {LARGEST_MB} MB a saved step may have", size >> 20),
        ));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(&path)
        .map(|f| flate2::read::DeflateDecoder::new(std::io::BufReader::new(f)).take(LARGEST_MB * 1024 * 1024))
        .and_then(|mut d| d.read_to_end(&mut bytes))
        .map_err(|e| refuse(&path, format!("it cannot be read ({e})")))?;
    let checkpoint: Checkpoint = bincode::deserialize(&bytes)
        .map_err(|e| refuse(&path, format!("it is not a saved step of this geoslip ({e})")))?;
    checkpoint.fits(model).map_err(|e| refuse(&path, e.to_string()))?;
    if checkpoint.state.u.len() != 2 * model.mesh.nodes.len() {
        return Err(refuse(&path, "its displacements do not match the model's nodes".into()));
    }
    Ok(checkpoint)
}

/// The saved steps in a folder, as `stage k: steps a–b` lines for a message.
fn saved_steps(folder: &Path) -> String {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return "the results hold no saved steps: they were written without them".into();
    };
    let mut names: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    names.sort();
    let found: Vec<String> = names
        .iter()
        .filter_map(|p| p.file_name()?.to_str()?.strip_suffix(".bin").map(|s| s.to_string()))
        .filter(|s| s.starts_with("stage-"))
        .collect();
    if found.is_empty() {
        "no step is saved there".into()
    } else if found.len() <= 6 {
        format!("saved: {}", found.join(", "))
    } else {
        format!("saved: {}, …, {} ({} in all)", found[..3].join(", "), found[found.len() - 1], found.len())
    }
}
