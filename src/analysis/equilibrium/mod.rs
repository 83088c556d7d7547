//! One increment iterated to equilibrium: each iteration linearises, solves, updates and asks
//! whether it has converged.
//!
//! ```text
//! [ K  sCᵀ ] { Δu    }   { f_ext − f_int(u) − Cᵀλ }
//! [ sC sD  ] { Δλ/s } = { −s·g(u)  (or −λ on a unit-diagonal row) }
//! ```
//!
//! K holds the elements and each spring's Ks·ℓ (constant stiffness: kept while the contact states
//! stay, so the factorisation is reused and an iteration costs one solve) or its tangent (Newton);
//! under the consistent Newton tangent the springs' shear is coupled to their normal multipliers.
//!
//! The files, in the order an increment uses them:
//! - `settle.rs`: the passes over an increment that settle an embedded reinforcement's σn;
//! - `iterations.rs` and `iterate.rs`: what an increment's iterations carry, and their loop;
//! - `linearise.rs`: the rows, the springs' laws, the soil and the springs' stiffness at the
//!   iterate ([`Linearisation`](linearise::Linearisation));
//! - `solve.rs`: the one place that chooses how the system is solved, among three paths
//!   ([`Path`](solve::Path)): on the interface alone, condensed, or in full;
//! - `interface_path.rs` and `condensation.rs`: the interface iteration's side (the elastic soil
//!   condensed onto the interface's unknowns, `linsol::condensed`) and its deferred interior;
//! - `check.rs`: the update of the active set and the convergence test, and `stall.rs`: an
//!   increment given up early when its iterations stop making progress.
//!
//! [`increment`] is the one way in.

mod check;
mod condensation;
mod interface_path;
mod iterate;
mod iterations;
mod linearise;
mod settle;
mod solve;
mod stall;

use super::context::Context;
use super::convergence::IncrementError;
use super::state::State;
use crate::dofs::DofMap;
use iterate::iterate;

pub use iterations::IncrementReport;

/// What an increment is for, which decides how it treats the σn of its embedded reinforcements
/// (the soil's normal stress across them) and when it is given up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Purpose {
    /// A loading step: iterated again until σn settles (`settle.rs`), and given up early when it
    /// stops making progress (`stall.rs`), so that a cutback comes sooner.
    Loading,
    /// A strength-reduction trial: σn taken as the iterations leave it, one pass, and given up
    /// only after `max_iterations` (the search's definition of failure; a trial near collapse
    /// may converge after a long stretch without progress). Its trials have always been single
    /// passes; the two differ in σn only on embedded faces whose σn is not frozen.
    StrengthTrial,
}

/// Iterate one increment to equilibrium.
///
/// # Errors
/// The increment's failure: no equilibrium (with the interface points that kept changing state),
/// a non-finite value, or a solver's error.
pub fn increment(
    cx: &mut Context,
    dofs: &DofMap,
    state: &mut State,
    purpose: Purpose,
) -> Result<IncrementReport, IncrementError> {
    let stall_iterations = cx.options.analysis.stall_iterations;
    match purpose {
        Purpose::Loading => settle::settled(cx, dofs, state, stall_iterations),
        Purpose::StrengthTrial => iterate(cx, dofs, state, 0),
    }
}
