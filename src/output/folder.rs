//! Names inside the output folder: names from the model made into path components that stay inside
//! it, the saved steps' folder, and the small helpers of the CSV files. Writing goes through the
//! folder's handle (`owned_folder.rs`).

use crate::error::Error;
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

/// The folder of saved steps inside a results folder (`checkpoints.rs`).
pub const CHECKPOINT_FOLDER: &str = "restart";

/// The error of a failed write to `path`.
pub(super) fn write_error(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Write { path: path.to_path_buf(), source }
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
