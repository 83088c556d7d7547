//! What one increment's iterations carry from one to the next, what an iteration's solve gives,
//! and the report of a converged increment.

use super::super::context::Context;
use super::super::singular::Fallbacks;
use super::super::springs::SpringResult;
use super::super::state::State;
use super::condensation::Deferred;
use super::stall::Progress;
use crate::element::soil_state::{SoilTrial, Tangent};
use crate::interface::active_set::Flips;
use crate::model::Scheme;

/// The springs' stiffness in an iteration's matrix: Ks·ℓ (constant stiffness, kept while the
/// contact states it was made with stay) or the law's tangent times ℓ (Newton).
#[derive(Default)]
pub(super) struct SpringStiffness {
    /// Each spring's contact state when the stiffness was made.
    pub contact: Vec<bool>,
    /// Each spring's stiffness times its tributary length.
    pub values: Vec<f64>,
}

/// A converged increment.
pub struct IncrementReport {
    pub iterations: usize,
    pub force_residual: f64,
    pub linear_residuals: Vec<f64>,
    pub springs: Vec<SpringResult>,
    pub state_changes: Vec<String>,
    /// The soil's Gauss-point states at equilibrium.
    pub soil: SoilTrial,
    /// The soil's and the bars' part of the internal force at equilibrium (the closing check's,
    /// `assembly::soil_and_bar_force_and_floor`), which the step's reactions are taken from.
    pub element_force: Vec<f64>,
    /// Its round-off floor (the same pass's).
    pub element_floor: f64,
    /// In a dynamic stage, the dynamic operator's part of it, D·u (the same pass's).
    pub operator_force: Option<Vec<f64>>,
}

/// What one increment's iterations carry from one to the next.
pub(super) struct Iterations {
    pub u_increment_start: Vec<f64>,
    pub linear_residuals: Vec<f64>,
    pub flips: Flips,
    pub state_changes: Vec<String>,
    /// The springs' stiffness of the last iteration's matrix (constant stiffness keeps it while the
    /// contact states stay).
    pub spring_stiffness: Option<SpringStiffness>,
    pub fallbacks: Fallbacks,
    /// The soil evaluated at the current iterate by the last convergence check.
    pub carried_soil: Option<SoilTrial>,
    /// The elements' part of the internal force at the current iterate, from the same check.
    pub carried_element_force: Option<Vec<f64>>,
    /// The round-off floor of the carried elements' force, where it was carried from the time
    /// step before (`Context::take_carried_force`), for an increment's first iteration.
    pub start_floor: Option<f64>,
    /// The iteration under way.
    pub iteration: usize,
    /// The last out-of-balance force and its reference.
    pub last_residual: Option<(f64, f64)>,
    /// This iteration solved the whole system condensed: the interior is in balance after it.
    pub condensed_solve: bool,
    /// The interface iteration under way ([`condensation::Deferred`]).
    pub deferred: Option<Deferred>,
    /// The residual at the last progress and the iterations since ([`stall`](super::stall)).
    pub progress: Progress,
}

/// An iteration's linear solution.
pub(super) struct Solution {
    /// [Δu on the free DOFs | Δλ/s].
    pub x: Vec<f64>,
    /// The constraint rows' scale s.
    pub scale: f64,
    /// The right-hand side it solved for.
    pub rhs: Vec<f64>,
}

impl Iterations {
    /// The start of an increment: nothing carried, but the elements' force at the end of the time
    /// step before, where it still holds (`Context::take_carried_force`).
    pub fn new(cx: &mut Context, state: &State, stall_iterations: usize) -> Iterations {
        let (carried_element_force, start_floor) = match cx.take_carried_force(&state.u) {
            Some((force, floor)) => (Some(force), Some(floor)),
            None => (None, None),
        };
        Iterations {
            u_increment_start: state.u.clone(),
            linear_residuals: Vec::new(),
            flips: Flips::new(),
            state_changes: Vec::new(),
            spring_stiffness: None,
            fallbacks: Fallbacks {
                elastic_springs: false,
                soil_tangent: match cx.options.analysis.scheme {
                    Scheme::Newton => Tangent::Consistent,
                    Scheme::NewtonSymmetric => Tangent::Symmetric,
                    Scheme::ConstantStiffness => Tangent::Elastic,
                },
                dependent_retries: 0,
            },
            carried_soil: None,
            carried_element_force,
            start_floor,
            iteration: 0,
            last_residual: None,
            condensed_solve: false,
            deferred: None,
            progress: Progress::new(stall_iterations),
        }
    }
}
