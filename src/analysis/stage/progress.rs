//! A stage once it is set up, with its progress, and where a converged increment sits in it.

use super::super::checkpoint::StageProgress;
use crate::dofs::DofMap;
use crate::model::StagePlan;
use std::time::Instant;

/// A stage once it is set up.
pub struct Stage<'a> {
    pub plan: &'a StagePlan,
    pub index: usize,
    /// The DOFs of this stage: held where supported, prescribed or not yet placed.
    pub dofs: DofMap,
    /// Converged steps so far.
    pub step: usize,
    /// Its set-up's results and the load factors still to reach: what a saved step keeps of it.
    pub progress: StageProgress,
}

/// Where a converged increment sits in its stage.
pub struct Increment {
    pub step: usize,
    pub load_factor: f64,
    /// The strength reduction factor of a strength-reduction stage.
    pub strength_factor: Option<f64>,
    pub cutbacks: usize,
    pub started: Instant,
    /// A loading history's factor reverses at this step.
    pub reversal: bool,
}
