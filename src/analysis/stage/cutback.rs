//! An increment iterated to equilibrium, or, when it fails in a way a smaller increment may not,
//! cut back: the state restored and the increment's midpoint put in front, up to `max_cutbacks`
//! times. Load steps and time steps alike.

use super::super::context::Context;
use super::super::equilibrium::{self, IncrementReport, Purpose};
use super::super::state::State;
use super::progress::Stage;
use crate::error::Error;

/// The increment to `target` from `snapshot` (the state before it): its report, or `None` when it
/// was cut back (the state is `snapshot` again).
///
/// # Errors
/// The increment's failure, placed in the model, the stage and the step, when it may not be cut
/// back (or no cutbacks remain).
pub fn solved_or_cut_back(
    cx: &mut Context,
    stage: &mut Stage,
    state: &mut State,
    snapshot: &State,
    target: f64,
) -> Result<Option<IncrementReport>, Error> {
    match equilibrium::increment(cx, &stage.dofs, state, Purpose::Loading) {
        Ok(report) => Ok(Some(report)),
        Err(e) => {
            let progress = &mut stage.progress;
            if e.retryable() && progress.cut_back(target, cx.options.analysis.max_cutbacks) {
                *state = snapshot.clone();
                return Ok(None);
            }
            Err(e.at(&cx.model.source, &stage.plan.name, stage.step + 1, progress.cutbacks))
        }
    }
}
