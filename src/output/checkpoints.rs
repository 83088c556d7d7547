//! The saved steps a run can continue from: `restart/stage-<k>-step-<nnnnn>.bin` in the results
//! folder, one per converged step of a loading stage, each the run's [`Checkpoint`] in bincode's
//! binary form (every number exactly as the run held it), deflated. Each is written as every result
//! file is ([`OwnedFolder::write`]: a temporary file, synced, renamed into place), so a killed run
//! leaves no truncated saved step.
//!
//! A file is [`MAGIC`], the length of the bincode bytes (u64, little-endian), their CRC-32
//! (u32, little-endian), then the deflated bytes. Reading one back checks the magic, refuses a
//! length above the run's memory limit before it inflates anything, inflates no more than that
//! length, and compares the CRC: a corrupted file is refused, and a file that inflates to more than
//! it says (a decompression bomb) stops at its word.
//!
//! `geoslip run MODEL --restart RESULTS --from STAGE:STEP` reads one back ([`read`]) and continues
//! from it when it fits the model: the same model where the state depends on it
//! ([`Checkpoint::fits`]), and every field in range ([`crate::analysis::resume_check`]).

use super::owned_folder::OwnedFolder;
use crate::analysis::Checkpoint;
use crate::error::Error;
use crate::model::Model;
use bincode::Options;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

pub use super::folder::CHECKPOINT_FOLDER as FOLDER;

/// The first bytes of a saved step: what it is and the layout's version.
pub const MAGIC: &[u8; 16] = b"geoslip-step\0\0\0\x04";

fn file_name(stage_index: usize, step: usize) -> String {
    format!("stage-{}-step-{step:05}.bin", stage_index + 1)
}

/// Write one saved step into `results/restart/`.
///
/// # Errors
/// [`Error::Write`] naming the file.
pub fn write(results: &OwnedFolder, checkpoint: &Checkpoint) -> Result<(), Error> {
    let (rel, bytes) = encoded(results, checkpoint)?;
    results.write(&rel, &bytes)
}

/// One saved step as its file in `results/restart/`: (its name in `results`, its bytes).
///
/// # Errors
/// [`Error::Write`] naming the file, when the step cannot be encoded.
fn encoded(results: &OwnedFolder, checkpoint: &Checkpoint) -> Result<(String, Vec<u8>), Error> {
    let rel = format!("{FOLDER}/{}", file_name(checkpoint.stage_index, checkpoint.step));
    let path = results.path().join(&rel);
    let fail = |source: std::io::Error| Error::Write { path: path.clone(), source };
    let bytes = bincode::serialize(checkpoint).map_err(|e| fail(std::io::Error::other(e.to_string())))?;
    let mut file = MAGIC.to_vec();
    file.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    file.extend_from_slice(&crc32fast::hash(&bytes).to_le_bytes());
    let mut deflate = flate2::write::DeflateEncoder::new(file, flate2::Compression::fast());
    deflate.write_all(&bytes).map_err(fail)?;
    let file = deflate.finish().map_err(fail)?;
    Ok((rel, file))
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
pub fn read(results: &Path, from: &From, model: &Model, memory_limit_mb: Option<f64>) -> Result<Checkpoint, Error> {
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
    let limit = crate::input_file::SizeLimit::of_memory(memory_limit_mb);
    let file = crate::input_file::read(&path, limit).map_err(|e| refuse(&path, format!("it cannot be read: {e}")))?;
    let bytes = inflate(&file, limit).map_err(|m| refuse(&path, m))?;
    let checkpoint: Checkpoint = bincode::DefaultOptions::new()
        .with_fixint_encoding()
        .with_limit(bytes.len() as u64)
        .deserialize(&bytes)
        .map_err(|e| refuse(&path, format!("it is not a saved step of this geoslip ({e})")))?;
    checkpoint.fits(model).map_err(|e| refuse(&path, e.to_string()))?;
    crate::analysis::resume_check::check(&checkpoint, model, index, from.step).map_err(|m| refuse(&path, m))?;
    Ok(checkpoint)
}

/// A saved step's bincode bytes: the header checked, inflated to no more than the length it states
/// (itself within `limit`), and the CRC compared.
fn inflate(file: &[u8], limit: crate::input_file::SizeLimit) -> Result<Vec<u8>, String> {
    let header = MAGIC.len() + 12;
    if file.len() >= header && file[..MAGIC.len() - 1] == MAGIC[..MAGIC.len() - 1] && file[15] != MAGIC[15] {
        return Err(format!(
            "it was written by a geoslip whose saved steps have layout {}, and this geoslip reads layout {}: run \
             the model from its start",
            file[15], MAGIC[15]
        ));
    }
    if file.len() < header || &file[..MAGIC.len()] != MAGIC {
        return Err("it is not a saved step of this geoslip (its first bytes are not a saved step's)".into());
    }
    let length = u64::from_le_bytes(file[16..24].try_into().expect("8 bytes"));
    let crc = u32::from_le_bytes(file[24..28].try_into().expect("4 bytes"));
    if length > limit.bytes {
        return Err(format!(
            "it says it holds {:.1} MB, and this run may use {:.1} MB ({})",
            length as f64 / 1048576.0,
            limit.bytes as f64 / 1048576.0,
            limit.why
        ));
    }
    let mut bytes = Vec::new();
    flate2::read::DeflateDecoder::new(&file[header..])
        .take(length + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("it cannot be inflated ({e})"))?;
    if bytes.len() as u64 != length {
        return Err(format!("it inflates to {} bytes where it says {length}: it is damaged", bytes.len()));
    }
    if crc32fast::hash(&bytes) != crc {
        return Err("its checksum does not match its contents: it is damaged or was changed".into());
    }
    Ok(bytes)
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
