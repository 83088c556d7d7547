//! What a run counts and times, and the warnings it gathers: the linear solver's own counts
//! ([`SolverStats`]) and the run's (equilibrium iterations, time on the interface, the residuals
//! and the output), owned by the analysis context and handed to the sink at every step.

pub use crate::linsol::linear_system::SolverStats;
use std::fmt;

/// A run's counts, times and warnings (`summary.json`'s `solver_stats`: one flat object).
#[derive(Debug, Default, Clone, serde::Serialize)]
pub struct RunStats {
    #[serde(flatten)]
    pub solver: SolverStats,
    /// Outer (equilibrium) iterations over the run.
    pub iterations: usize,
    /// Time on interface points: rows, laws, active set, tributary clipping, re-association.
    pub interface_seconds: f64,
    /// Time computing the out-of-balance force: the checks', and the line search's trial steps.
    pub residual_seconds: f64,
    /// Time computing and writing each step's results.
    pub output_seconds: f64,
    /// Time saving the steps a run can continue from (the state copied, encoded and handed to
    /// the writer).
    pub checkpoint_seconds: f64,
    /// Time setting the run up: the soil's set-up, the element matrices, the solver, the initial
    /// state.
    pub setup_seconds: f64,
    /// Time setting the stages up: soil placed and removed, water, K0 stresses, contacts, DOFs,
    /// loads, σn frozen.
    pub stage_setup_seconds: f64,
    /// Time in the stages' increments (or strength-reduction searches), everything in them: the
    /// times above but the set-ups' are parts of it.
    pub increments_seconds: f64,
    /// Diagnostics that do not stop a run.
    pub warnings: Warnings,
}

/// A diagnostic that does not stop a run.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// The factorisation's negative pivots differ from the active multipliers.
    InertiaMismatch { backend: &'static str, negative: usize, active: usize },
    /// The interface iteration's condensed solve failed: the run goes on with the full system.
    CondensedSolveFailed { error: String },
    /// A stage freezes σn where no interface point in contact is compressed yet.
    UnloadedFreeze { stage: String, unloaded: usize },
    /// The tangent with sliding points was singular: those points continued with Ks.
    SlidingTangentSingular,
    /// The yielded soil's consistent tangent was singular: the elastic stiffness took over.
    YieldedTangentSingular,
    /// A reinforcement's applied and carried forces differ well beyond the force tolerance.
    ReinforcementBalance {
        interface: String,
        applied: [f64; 2],
        carried: [f64; 2],
        mismatch: f64,
        /// What the mismatch is a share of.
        of: &'static str,
        stage: String,
        step: usize,
    },
    /// A solved matrix's diagonal spans more than double precision factorises reliably.
    IllConditioned { softest: (f64, String), stiffest: (f64, String), ratio: f64 },
}

impl Warning {
    /// Whether a run that has `self` already has nothing new in `other`: one warning per
    /// reinforcement for its balance, one ill-conditioning warning a run, and no repeats.
    fn covers(&self, other: &Warning) -> bool {
        match (self, other) {
            (
                Warning::ReinforcementBalance { interface: a, .. },
                Warning::ReinforcementBalance { interface: b, .. },
            ) => a == b,
            (Warning::IllConditioned { .. }, Warning::IllConditioned { .. }) => true,
            _ => self == other,
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::InertiaMismatch { backend, negative, active } => write!(
                f,
                "{backend} reports {negative} negative pivots for {active} active multipliers: \
                 some constraint rows may be dependent, or K is not positive definite on their null space"
            ),
            Warning::CondensedSolveFailed { error } => write!(
                f,
                "the interface iteration's condensed solve failed ({error}); the run goes on with the full system"
            ),
            Warning::UnloadedFreeze { stage, unloaded } => write!(
                f,
                "stage \"{stage}\" freezes σn at its start, where no interface point in contact is compressed yet ({unloaded} points at σn ≤ 0): their shear strength through the stage is the cohesion alone; set freeze_normal_stress = false on that stage"
            ),
            Warning::SlidingTangentSingular => f.write_str(
                "the tangent with sliding interface points was singular in some increments (a slack \
                 reinforcement held only by sliding points); they continued with Ks on those points",
            ),
            Warning::YieldedTangentSingular => f.write_str(
                "the consistent tangent of the yielded soil was singular in some increments; they \
                 continued on the elastic soil stiffness",
            ),
            Warning::ReinforcementBalance { interface, applied, carried, mismatch, of, stage, step } => write!(
                f,
                "reinforcement \"{}\": the forces applied to its nodes ({:.6e}, {:.6e}) and those its interfaces carry ({:.6e}, {:.6e}) differ by {:.1e} of {of}, beyond ten times the force tolerance (first in stage \"{}\", step {})",
                interface, applied[0], applied[1], carried[0], carried[1], mismatch, stage, step
            ),
            Warning::IllConditioned { softest, stiffest, ratio } => write!(
                f,
                "the stiffness matrix is ill-conditioned: its diagonal ranges from {:.3e} at {} to {:.3e} at {} (a ratio \
                 of {:.1e}, beyond the 1e12 that double precision factorises reliably); the results carry round-off: \
                 bring the stiffnesses closer (the soil's Young's modulus against the reinforcement's EA and the \
                 interfaces' Ks, in consistent units)",
                softest.0, softest.1, stiffest.0, stiffest.1, ratio
            ),
        }
    }
}

/// A run's warnings, in the order they arose, each kind at most as often as it says something new.
#[derive(Debug, Default, Clone)]
pub struct Warnings(Vec<Warning>);

impl Warnings {
    /// Add `warning` unless an earlier one covers it.
    pub fn add(&mut self, warning: Warning) {
        if !self.0.iter().any(|w| w.covers(&warning)) {
            self.0.push(warning);
        }
    }

    pub fn iter(&self) -> std::slice::Iter<'_, Warning> {
        self.0.iter()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// The warnings as the summary and the report state them.
    pub fn texts(&self) -> Vec<String> {
        self.0.iter().map(Warning::to_string).collect()
    }
}

impl<'a> IntoIterator for &'a Warnings {
    type Item = &'a Warning;
    type IntoIter = std::slice::Iter<'a, Warning>;

    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}

impl serde::Serialize for Warnings {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.0.iter().map(Warning::to_string))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reinforcement_is_warned_of_once_and_ill_conditioning_once_a_run() {
        let balance = |interface: &str, step| Warning::ReinforcementBalance {
            interface: interface.into(),
            applied: [1.0, 0.0],
            carried: [0.9, 0.0],
            mismatch: 0.1,
            of: "the applied force",
            stage: "pull".into(),
            step,
        };
        let ill = |ratio| Warning::IllConditioned { softest: (1.0, "a".into()), stiffest: (1e13, "b".into()), ratio };
        let mut w = Warnings::default();
        for warning in [balance("grid", 3), balance("grid", 4), balance("sheet", 4), ill(1e13), ill(1e14)] {
            w.add(warning);
        }
        w.add(Warning::SlidingTangentSingular);
        w.add(Warning::SlidingTangentSingular);
        let texts = w.texts();
        assert_eq!(texts.len(), 4, "{texts:?}");
        assert!(texts[0].starts_with("reinforcement \"grid\"") && texts[0].ends_with("step 3)"));
        assert!(texts[1].starts_with("reinforcement \"sheet\""));
        assert!(texts[2].contains("a ratio of 1.0e13"));
    }
}
