//! A stage once it is set up, with its progress (what a saved step keeps of it), and where a
//! converged increment sits in it.

use super::super::predictor::LastIncrement;
use crate::dofs::DofMap;
use crate::model::StagePlan;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// A stage once it is set up.
pub struct Stage<'a> {
    pub plan: &'a StagePlan,
    pub index: usize,
    /// The DOFs of this stage: held where supported, prescribed or not yet placed.
    pub dofs: DofMap,
    /// Converged steps so far.
    pub step: usize,
    /// The supported DOFs this stage frees (a dynamic stage's absorbing sides), held again when it
    /// ends.
    pub freed: Vec<usize>,
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

/// Where a stage is: its set-up's results and the load factors still to reach.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StageProgress {
    pub redundant: Vec<String>,
    pub force: Vec<f64>,
    pub f_ext_start: Vec<f64>,
    pub unbalance: Vec<f64>,
    /// Displacements when the stage started (prescribed displacements count from them).
    pub u_start: Vec<f64>,
    /// Load factors still to reach (empty: the stage is complete).
    pub targets: Vec<f64>,
    pub reached: f64,
    /// Steps of the plan reached.
    pub planned: usize,
    /// Cutbacks of the increment in progress.
    pub cutbacks: usize,
    /// The stage's last converged increment (what `extrapolation = "linear"` carries on).
    pub last: Option<LastIncrement>,
}

impl StageProgress {
    /// Halve the increment to `target`, its midpoint put in front, when fewer than `max` cutbacks
    /// were made; whether it was.
    pub fn cut_back(&mut self, target: f64, max: usize) -> bool {
        if self.cutbacks >= max {
            return false;
        }
        self.targets.insert(0, 0.5 * (self.reached + target));
        self.cutbacks += 1;
        true
    }

    /// Whether `target` is the plan's next step (`planned`: the plan's factors), not a cutback's
    /// midpoint; counted if it is.
    pub fn count_planned(&mut self, planned: &[f64], target: f64) -> bool {
        let is = planned.get(self.planned) == Some(&target);
        if is {
            self.planned += 1;
        }
        is
    }

    /// The increment to `target` has converged (`planned`: a step of the plan, which ends its
    /// cutbacks).
    pub fn reach(&mut self, target: f64, planned: bool) {
        self.targets.remove(0);
        self.reached = target;
        if planned {
            self.cutbacks = 0;
        }
    }
}
