//! What a run hands out as it goes: each converged step (its results and its record) and each
//! factor of safety, to a [`StepSink`] that writes or keeps them.

use super::checkpoint::Checkpoint;
use super::results::{ReinforcementBalance, StepResults};
use super::stats::RunStats;
use crate::error::Error;
use crate::interface::reassociate::Reassociation;
use crate::model::Model;

/// Receives each converged step as soon as it exists, so that a later failure never loses it.
pub trait StepSink {
    /// Step `step` of a run of `model` (whose Gauss-point results it makes, if it wants them:
    /// [`StepResults::stresses`]).
    fn step_done(
        &mut self,
        model: &Model,
        step: &StepResults,
        record: &StepRecord,
        stats: &RunStats,
    ) -> Result<(), Error>;

    /// The result of a strength-reduction stage, after its last step.
    fn factor_of_safety(&mut self, _fs: &FactorOfSafety) -> Result<(), Error> {
        Ok(())
    }

    /// Whether the sink keeps what a run needs to continue from each step (the run builds the
    /// checkpoints only then).
    fn keeps_checkpoints(&self) -> bool {
        false
    }

    /// What the run needs to continue from the step just handed over (after `step_done`), the
    /// sink's to keep.
    fn checkpoint(&mut self, _checkpoint: Checkpoint) -> Result<(), Error> {
        Ok(())
    }
}

/// The factor of safety found by a strength-reduction stage.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FactorOfSafety {
    pub stage: String,
    /// FS: the largest strength reduction factor with equilibrium.
    pub value: f64,
    /// The smallest factor tried without equilibrium; `None` when every factor up to `max_factor`
    /// found one (FS is then at least `value`).
    pub failed_at: Option<f64>,
    /// `interfaces` or `soil and interfaces`.
    pub reduced: &'static str,
    /// Every factor tried, and whether it found equilibrium.
    pub trials: Vec<(f64, bool)>,
    /// Why the search found no equilibrium at `failed_at`: how the iterations ended, the soil
    /// yielding, and the reinforcement that ruptured on the way (rolled back with the trial).
    pub failure: Option<String>,
}

/// Keeps every converged step in memory, its Gauss-point results made (for tests and for programs
/// that use geoslip as a library).
#[derive(Debug, Default)]
pub struct Collect {
    pub steps: Vec<(StepRecord, StepResults)>,
    pub factors_of_safety: Vec<FactorOfSafety>,
}

impl StepSink for Collect {
    fn step_done(&mut self, model: &Model, step: &StepResults, record: &StepRecord, _: &RunStats) -> Result<(), Error> {
        self.steps.push((record.clone(), step.kept(model)));
        Ok(())
    }

    fn factor_of_safety(&mut self, fs: &FactorOfSafety) -> Result<(), Error> {
        self.factors_of_safety.push(fs.clone());
        Ok(())
    }
}

impl Collect {
    /// The last converged step.
    pub fn last(&self) -> Option<&StepResults> {
        self.steps.last().map(|(_, r)| r)
    }
}

impl StepRecord {
    /// Where the step is in its stage, in words: its time in a dynamic stage, the strength
    /// reduction factor in a strength-reduction search, its load factor otherwise.
    pub fn position(&self) -> String {
        match (self.time, self.strength_factor) {
            (Some(t), _) => format!("t = {t:.4} s"),
            (None, Some(f)) => format!("strengths divided by {f:.4}"),
            (None, None) => format!("load factor {:.4}", self.load_factor),
        }
    }
}

/// One converged step, as the run summary lists it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepRecord {
    pub stage: String,
    pub stage_index: usize,
    pub step: usize,
    pub load_factor: f64,
    /// The time [s] from the start of a dynamic stage.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The strength reduction factor F of a strength-reduction stage (strengths divided by F).
    pub strength_factor: Option<f64>,
    /// A loading history's factor reverses at this step (cyclic loading).
    pub reversal: bool,
    pub iterations: usize,
    /// How many times this increment was cut back before it converged.
    pub cutbacks: usize,
    /// Out-of-balance force after the last iteration, relative to the reference force.
    pub force_residual: f64,
    /// ‖Ax − b‖/‖b‖ of each linear solve in this step.
    pub linear_residuals: Vec<f64>,
    pub seconds: f64,
    /// Interface points whose normal row repeats another row on the free DOFs (see NormalState).
    pub redundant_rows: Vec<String>,
    /// Interface points that changed state (released, re-activated, held) in this step.
    pub state_changes: Vec<String>,
    /// Points re-associated with another master segment after this step.
    pub reassociations: Vec<Reassociation>,
    /// Points now sliding at their strength.
    pub sliding_points: usize,
    /// Soil Gauss points on the yield surface.
    pub yielding_points: usize,
    /// Points with a tangential law that are in contact.
    pub contact_points: usize,
    /// Force balance of every reinforcement: what is applied to its nodes against what its interfaces
    /// carry.
    pub balance: Vec<ReinforcementBalance>,
}
