//! When an increment has converged, and how it failed when it has not.
//!
//! Converged when the out-of-balance force is small (against the applied forces and the reactions,
//! or below the round-off floor), the gaps of the active rows are closed, no interface point changed
//! state, and the displacement correction is small against the increment (or against the
//! displacements so far, for an increment that moves almost nothing) or this was the first solve. A
//! residual that is not finite is a divergence.

use super::non_finite::NonFinite;
use super::springs::InterfaceIterate;
use super::state::State;
use crate::assembly::{add_spring_forces, soil_and_bar_force, ElementMatrices, SoilView};
use crate::dofs::DofMap;
use crate::element::soil_state::SoilTrial;
use crate::error::{Error, SolveError};
use crate::interface::rows::{constraint_force, multiplier_is_active, InterfaceRows};
use crate::interface::NormalState;
use crate::model::AnalysisSettings;

/// Why an increment failed, before the stage and step are known.
pub enum IncrementError {
    Solve(SolveError),
    /// The matrix was singular beyond the recoveries at an iterate that had left the last
    /// equilibrium (a slack sheet come loose from the soil, a local mechanism the iterate ran
    /// into): a smaller increment may not go there. At the last equilibrium itself the singular
    /// matrix is the model's, and [`IncrementError::Solve`] names what is unconstrained at once.
    SingularIterate {
        iteration: usize,
        source: SolveError,
    },
    /// A number that is not finite appeared in an iteration.
    NonFinite {
        iteration: usize,
        first: NonFinite,
    },
    NotConverged {
        iterations: usize,
        residual: f64,
        reference: f64,
        unsettled: Vec<String>,
        yielding: usize,
        /// Given up after this many iterations without progress (`stall_iterations`).
        stalled: Option<usize>,
    },
}

impl IncrementError {
    /// One line on how the increment failed.
    pub fn describe(&self) -> String {
        match self {
            IncrementError::Solve(e) => format!("the solve failed: {e}"),
            IncrementError::SingularIterate { iteration, source } => {
                format!("at iteration {iteration}, away from the last equilibrium, {source}")
            }
            IncrementError::NonFinite { iteration, first } => {
                format!("a non-finite number ({}) in iteration {iteration}, first in {}", first.value, first.location)
            }
            IncrementError::NotConverged { iterations, residual, reference, unsettled, yielding, stalled } => {
                let mut s = format!(
                    "no equilibrium after {iterations} iterations (force residual {:.1e} of the reference)",
                    residual / reference
                );
                if let Some(n) = stalled {
                    s += &format!("; no progress in its last {n}");
                }
                if !unsettled.is_empty() {
                    s += &format!("; {} interface points kept changing state", unsettled.len());
                }
                if *yielding > 0 {
                    s += &format!("; {yielding} soil Gauss points on the yield surface");
                }
                s
            }
        }
    }

    /// A failure that a smaller increment may cure (an overflow from too large a step may be).
    pub fn retryable(&self) -> bool {
        matches!(
            self,
            IncrementError::NotConverged { .. }
                | IncrementError::NonFinite { .. }
                | IncrementError::SingularIterate { .. }
        )
    }

    /// The run's error, at a stage and step.
    pub fn at(self, file: &std::path::Path, stage: &str, step: usize, cutbacks: usize) -> Error {
        match self {
            IncrementError::Solve(source) => {
                Error::Solve { file: file.to_path_buf(), stage: stage.to_string(), step, source }
            }
            IncrementError::SingularIterate { iteration, source } => Error::SingularIterate {
                file: file.to_path_buf(),
                stage: stage.to_string(),
                step,
                iteration,
                cutbacks,
                source,
            },
            IncrementError::NonFinite { iteration, first } => Error::NonFinite {
                file: file.to_path_buf(),
                stage: stage.to_string(),
                step,
                iteration,
                value: first.value,
                location: first.location,
                cutbacks,
            },
            IncrementError::NotConverged { iterations, residual, reference, unsettled, yielding, stalled } => Error::NotConverged {
                file: file.to_path_buf(),
                stage: stage.to_string(),
                step,
                iterations,
                residual,
                reference,
                hint: format!(
                    "after {cutbacks} cutbacks. {}{}{}Try more load factors in this stage, a larger max_iterations, or the newton scheme",
                    if unsettled.is_empty() {
                        String::new()
                    } else {
                        format!("Interface points that kept changing state: {}. ", cap(unsettled).join("; "))
                    },
                    if yielding > 0 {
                        format!(
                            "{yielding} soil Gauss points were on the yield surface at the last iteration: the soil may be \
                             collapsing (a limit load reached). "
                        )
                    } else {
                        String::new()
                    },
                    match stalled {
                        Some(n) => format!(
                            "The last increment was given up after {n} iterations in which the residual did not fall \
                             (a larger stall_iterations, or 0, lets it iterate on). "
                        ),
                        None => String::new(),
                    }
                ),
            },
        }
    }
}

/// The measures of one iterate that decide convergence.
pub struct Measures {
    /// ‖out-of-balance force on the free DOFs‖.
    pub residual: f64,
    /// The reference force: applied loads and reactions.
    pub reference: f64,
    /// The round-off floor of the residual (see `assembly::soil_and_bar_force_and_floor`).
    pub floor: f64,
    /// No interface point changed state and no bar ruptured in this iteration.
    pub settled: bool,
    pub gaps_closed: bool,
    /// The displacement correction is small (or this was the first solve).
    pub displacement_ok: bool,
}

/// What the convergence test reads of an iterate besides the elements' force: the interfaces at
/// the iterate and their rows' gaps, whether any point changed state (or a bar ruptured), and the
/// last correction.
pub struct IterateCheck<'a> {
    pub interface: &'a InterfaceIterate,
    pub gaps: &'a [f64],
    pub settled: bool,
    /// The last displacement correction is small ([`displacement_ok`]).
    pub displacement_ok: bool,
    /// The model's characteristic length (the gaps' floor).
    pub characteristic: f64,
}

impl Measures {
    /// The measures of the iterate `check` describes, from the elements' part of the internal
    /// force `element` and its round-off `floor`.
    pub fn of(check: &IterateCheck, element: &[f64], floor: f64, state: &State, dofs: &DofMap) -> Measures {
        let (residual, reference) = balance(element, &check.interface.rows, &check.interface.taus(), state, dofs);
        Measures {
            residual,
            reference,
            floor,
            settled: check.settled,
            gaps_closed: gaps_closed(check.gaps, state, dofs, check.characteristic),
            displacement_ok: check.displacement_ok,
        }
    }

    /// The out-of-balance force below which the forces balance: the tolerance times the
    /// reference, or the round-off floor.
    pub fn threshold(&self, settings: &AnalysisSettings) -> f64 {
        (settings.force_tolerance * self.reference).max(self.floor)
    }

    pub fn converged(&self, settings: &AnalysisSettings) -> bool {
        self.settled && self.residual <= self.threshold(settings) && self.gaps_closed && self.displacement_ok
    }
}

/// Whether the correction `correction2` (squared) is small against the increment so far or the
/// displacements so far; the first solve of an increment always is (a first solve that already
/// balances the forces had a linear increment).
pub fn displacement_ok(
    settings: &AnalysisSettings,
    iteration: usize,
    correction2: f64,
    u: &[f64],
    u_increment_start: &[f64],
) -> bool {
    let increment2: f64 = u.iter().zip(u_increment_start).map(|(a, b)| (a - b).powi(2)).sum();
    let total2: f64 = u.iter().map(|a| a * a).sum();
    iteration == 1
        || correction2.sqrt()
            <= settings.displacement_tolerance * increment2.sqrt().max(total2.sqrt()).max(f64::MIN_POSITIVE)
}

/// ‖out-of-balance force on the free DOFs‖, the reference force (applied loads and reactions), and
/// the elements' part of the internal force (`assembly::soil_and_bar_force`), which the next iteration's
/// right-hand side reuses: nothing it depends on changes in between.
pub fn out_of_balance(
    elements: &ElementMatrices,
    soil_trial: &SoilTrial,
    rows: &InterfaceRows,
    taus: &[f64],
    state: &State,
    dofs: &DofMap,
) -> (f64, f64, Vec<f64>) {
    let view = SoilView { field: &state.soil, trial: soil_trial };
    let element = soil_and_bar_force(elements, view, &state.bars, &state.u);
    let (residual, reference) = balance(&element, rows, taus, state, dofs);
    (residual, reference, element)
}

/// ‖out-of-balance force on the free DOFs‖ and the reference force, from the elements' part of the
/// internal force `element` (however it was found).
fn balance(element: &[f64], rows: &InterfaceRows, taus: &[f64], state: &State, dofs: &DofMap) -> (f64, f64) {
    let n_dof = state.u.len();
    let mut f_int = element.to_vec();
    add_spring_forces(&mut f_int, rows, taus);
    let f_c = constraint_force(rows, &state.lambda, n_dof);
    let mut r2 = 0.0;
    let mut reference2 = 0.0;
    for d in 0..n_dof {
        let r = state.f_ext[d] - f_int[d] - f_c[d];
        if dofs.equation[d].is_some() {
            r2 += r * r;
            reference2 += state.f_ext[d].powi(2);
        } else {
            reference2 += r * r; // reactions
        }
    }
    (r2.sqrt(), reference2.sqrt().max(f64::MIN_POSITIVE))
}

/// Whether every active row's gap is closed (to 10⁻⁹ of the largest displacement, or of 10⁻⁶ of
/// the `characteristic` length).
fn gaps_closed(gaps: &[f64], state: &State, dofs: &DofMap, characteristic: f64) -> bool {
    let scale = state.u.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-6 * characteristic);
    gaps.iter().enumerate().all(|(k, g)| {
        let m = dofs.multipliers[k];
        let held = !m.tangential
            && matches!(
                state.interfaces[m.interface].faces[m.face].points[m.point].normal_state,
                NormalState::Held { .. }
            );
        held || !multiplier_is_active(&state.interfaces, m) || g.abs() <= 1e-9 * scale
    })
}

/// At most 12 entries of a list for a message, and how many more there are.
pub fn cap(mut list: Vec<String>) -> Vec<String> {
    if list.len() > 12 {
        let more = list.len() - 12;
        list.truncate(12);
        list.push(format!("and {more} more"));
    }
    list
}
