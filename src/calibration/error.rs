//! What can stop a calibration, with the file, the line, the column or the parameter concerned.

use std::path::PathBuf;

/// A calibration that could not give parameters.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CalibrationError {
    #[error("{path}: cannot read: {source}")]
    Read { path: PathBuf, source: crate::input_file::Unreadable },
    /// The calibration file: a field missing, unknown or out of range.
    #[error("{path}: {field}: {message}")]
    Spec { path: PathBuf, field: String, message: String },
    /// The measured curves: a header without units, a value that is not a number, too few points.
    #[error("{path}{}{}: {message}", .line.map(|l| format!(", line {l}")).unwrap_or_default(),
            .column.as_ref().map(|c| format!(", column \"{c}\"")).unwrap_or_default())]
    Data { path: PathBuf, line: Option<usize>, column: Option<String>, message: String },
    /// The curves cannot tell these parameters apart (or leave one without any effect): no number is
    /// given for them.
    #[error(
        "the data cannot identify {}: {reason}. Add curves that do (or hold the parameters at known values \
         under [fixed])", and_list(.parameters)
    )]
    Unidentifiable { parameters: Vec<String>, reason: String },
    /// The least-squares iteration stopped without converging.
    #[error("the fit did not converge after {evaluations} evaluations of the model: {reason}")]
    NotConverged { evaluations: usize, reason: String },
    /// A finite-element run of the test (the pull-out box) failed.
    #[error("the finite-element model of the test at {condition}: {source}")]
    Model { condition: String, source: Box<crate::Error> },
    #[error("{path}: cannot write output: {source}")]
    Write { path: PathBuf, source: std::io::Error },
}

/// "a", "a and b", "a, b and c".
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}
