//! What a run may be asked to do: a backend with its settings, and the model's `[analysis]`
//! settings.

use crate::linsol::{Backend, SolverOptions};
use crate::model::{AnalysisSettings, Model};

/// What a run may be asked to do: a backend and the model's `[analysis]` settings
/// ([`RunOptions::for_model`]).
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub backend: Backend,
    pub analysis: AnalysisSettings,
    /// Ordering, out-of-core and memory limit of the backend.
    pub solver: SolverOptions,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions { backend: Backend::Auto, analysis: AnalysisSettings::default(), solver: SolverOptions::default() }
    }
}

impl RunOptions {
    /// The model's `[analysis]` settings with a backend and its default settings.
    pub fn for_model(model: &Model, backend: Backend) -> RunOptions {
        RunOptions { backend, analysis: model.analysis.clone(), solver: SolverOptions::default() }
    }
}
