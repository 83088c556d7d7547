//! The interface iteration: an iteration's system solved with the elastic soil condensed onto the
//! interface's unknowns ([`crate::linsol::condensed`]).
//!
//! While the soil is elastic, only the interface changes from one iteration to the next: the
//! springs' tangents, which rows hold, which segment each point faces. The soil is condensed onto
//! the unknowns the interface can touch (the reinforcements' DOFs, every DOF of the nodes on a
//! contact face's master path, every multiplier) once per soil (its fingerprint); an iteration then costs one dense
//! LU of that small system (when its matrix changed) and one condensation and expansion, whatever
//! the scheme's tangent. The answer is the direct solve's, to its residual check.
//!
//! Within an increment the iterations go on on the kept unknowns alone ([`Deferred`]), the interior
//! following once at the end; an increment whose load moves the kept unknowns alone (a pulled head)
//! starts there too ([`start_in_balance`]), so that it costs one sparse solve, the interior's
//! following.
//!
//! It falls back to the full system, automatically, where it does not apply: a soil element
//! yielding (its tangent changes the soil part), a backend with no condensed path (the dense
//! reference, which stays the independent check), an interior the soil alone cannot hold (the
//! factorisation finds it singular), or more kept unknowns than a dense system should have.

use super::super::state::State;
use super::super::stats::{RunStats, SolverStats, Warning};
use crate::assembly::{bar_force, ElementMatrices, SystemInputs};
use crate::dofs::DofMap;
use crate::linsol::condensed::{CondensedError, CondensedSystem, InterfacePart, KeptUnknowns, SoilPart};
use crate::linsol::csc::Triplets;
use std::rc::Rc;

/// Largest number of kept unknowns condensed onto, and the largest share of all the unknowns they
/// may be. The kept system holds S's dense block and the dense factors, at most 16·m² bytes (2.3 GB
/// at the limit). The 1.6·10⁶-unknown pull-out keeps about 9100 (docs/performance.md).
pub const MAX_KEPT: usize = 12000;
const MAX_KEPT_SHARE: f64 = 0.5;

/// The unknowns an interface can touch: every multiplier; the DOFs of every bar; the DOFs of every
/// master node and slave point of every contact face; any DOF no present soil element holds.
pub fn kept_equations(system: &SystemInputs) -> KeptUnknowns {
    let (elements, dofs) = (system.elements, system.dofs);
    let mut keep = vec![false; dofs.size()];
    let mut mark = |d: usize| {
        if let Some(e) = dofs.equation[d] {
            keep[e] = true;
        }
    };
    for b in 0..elements.bars.len() {
        for &d in elements.bar_dofs(b) {
            mark(d);
        }
    }
    for face in system.interfaces.iter().flat_map(|i| &i.faces) {
        for &n in face.master.iter().chain(face.points.iter().map(|p| &p.slave)) {
            mark(2 * n);
            mark(2 * n + 1);
        }
    }
    let mut held_by_soil = vec![false; dofs.equation.len()];
    let first_bar = elements.bars.first().map_or(elements.blocks.len(), |b| b.block);
    let present = system.soil.field.active_words();
    for (b, (dl, _)) in elements.blocks[..first_bar].iter().enumerate() {
        if present[b / 64] >> (b % 64) & 1 == 1 {
            for &d in dl {
                held_by_soil[d] = true;
            }
        }
    }
    for (d, held) in held_by_soil.iter().enumerate() {
        if !held {
            mark(d);
        }
    }
    for k in 0..dofs.multipliers.len() {
        keep[dofs.multiplier_equation(k)] = true;
    }
    KeptUnknowns::from_marks(&keep)
}

/// What a condensed solve gives back.
pub enum Condensed {
    /// The solution and its relative residual.
    Solved(Vec<f64>, f64),
    /// Not this iteration: solve the full system.
    NotHere,
}

/// The unknowns an iteration's system (`system`) would be condensed onto, when the run condenses
/// (`condensed` is set) and this iteration allows it: its soil elastic, and the interface's
/// unknowns few enough. Soil alone, with no interface or bar, has nothing to condense onto: its
/// system is the full system's solve.
pub fn condensable(condensed: &Option<CondensedSystem>, system: &SystemInputs) -> Option<Rc<KeptUnknowns>> {
    condensed.as_ref()?;
    if system.interfaces.is_empty() && system.elements.bars.is_empty() {
        return None;
    }
    if system.soil.trial.tangents.iter().any(Option::is_some) {
        return None;
    }
    let kept = Rc::new(kept_equations(system));
    if kept.is_empty() || kept.len() > MAX_KEPT || kept.len() as f64 > MAX_KEPT_SHARE * system.dofs.size() as f64 {
        return None;
    }
    Some(kept)
}

/// Solve an iteration's system condensed onto `kept` ([`condensable`]). `system`: the iteration's
/// inputs; `key`: the fingerprint of its whole matrix. A backend error turns condensation off for
/// the rest of the run, with a warning.
pub fn solve(
    condensed: &mut Option<CondensedSystem>,
    stats: &mut RunStats,
    system: SystemInputs,
    kept: Rc<KeptUnknowns>,
    key: u64,
    rhs: &[f64],
) -> Condensed {
    let Some(solver) = condensed.as_mut() else { return Condensed::NotHere };
    let t = std::time::Instant::now();
    let change: Triplets = system.assemble_reinforcement_and_interface();
    let soil_key = system.soil_fingerprint();
    stats.solver.assembly_seconds += t.elapsed().as_secs_f64();
    if !kept.holds(&change) {
        return Condensed::NotHere;
    }
    let assemble = || system.assemble_soil();
    let times = |x: &[f64]| system.soil_times(x);
    let soil = SoilPart { kept: &kept, key: soil_key, assemble: &assemble, times: &times };
    let interface = InterfacePart { key, assemble: &|| change.clone() };
    match solver.solve(&mut stats.solver, &soil, &interface, rhs) {
        Ok((x, residual)) => Condensed::Solved(x, residual),
        // the dense interface system, or a soil interior that the soil alone cannot hold: the full
        // system's recoveries and diagnosis take over
        Err(CondensedError::Fallback(_)) => Condensed::NotHere,
        Err(CondensedError::Backend(e)) => {
            stats.warnings.add(Warning::CondensedSolveFailed { error: e.to_string() });
            *condensed = None;
            Condensed::NotHere
        }
    }
}

/// One increment's interface iteration after a condensed solve of the whole system: the interior
/// stays where that solve left it, in balance (the soil is linear and carries no interface force
/// there), and each correction moves the kept unknowns alone. The soil's force on them is then its
/// force at the start plus S·(their movement since); the interior follows at the end
/// ([`Deferred::finish`]), with one condensation and one expansion.
pub struct Deferred {
    /// The soil part the condensation was made for.
    soil_key: u64,
    kept: Rc<KeptUnknowns>,
    /// Each kept equation's DOF (`None`: a multiplier).
    kept_dof: Vec<Option<usize>>,
    /// The soil elements' force at every DOF when the interior was balanced.
    soil_force: Vec<f64>,
    /// The corrections of each kept unknown since.
    moved: Vec<f64>,
    /// S·moved: the change of the soil's force on the kept unknowns since (summed solve by solve,
    /// from the products each solve's residual check makes).
    soil_moved: Vec<f64>,
    /// The round-off floor of the residual then.
    pub floor: f64,
}

impl Deferred {
    /// Start from a balanced interior: `balanced` holds the elements' part of the internal force
    /// (soil and bars) at the current displacements and the residual's round-off floor there.
    pub fn start(
        condensed: &CondensedSystem,
        elements: &ElementMatrices,
        dofs: &DofMap,
        state: &State,
        balanced: BalancedInterior,
    ) -> Option<Deferred> {
        let BalancedInterior { element_force, floor } = balanced;
        let (kept, soil_key) = condensed.condensed_on()?;
        let mut dof_of = vec![None; dofs.size()];
        for (d, e) in dofs.equation.iter().enumerate() {
            if let Some(e) = e {
                dof_of[*e] = Some(d);
            }
        }
        let bars = bar_force(elements, &state.bars, &state.u);
        Some(Deferred {
            soil_key,
            kept: kept.clone(),
            kept_dof: kept.equations().iter().map(|&e| dof_of[e]).collect(),
            soil_force: element_force.iter().zip(&bars).map(|(f, b)| f - b).collect(),
            moved: vec![0.0; kept.len()],
            soil_moved: vec![0.0; kept.len()],
            floor,
        })
    }

    /// The elements' part of the internal force now: the soil's force at the start plus S·moved on
    /// the kept DOFs (elsewhere as at the start), and the bars' at the current displacements.
    pub fn element_force(&self, elements: &ElementMatrices, state: &State) -> Vec<f64> {
        let mut f = bar_force(elements, &state.bars, &state.u);
        for (fi, s) in f.iter_mut().zip(&self.soil_force) {
            *fi += s;
        }
        for (k, &change) in self.soil_moved.iter().enumerate() {
            if let Some(d) = self.kept_dof[k] {
                f[d] += change;
            }
        }
        f
    }

    /// The interior follows the kept unknowns' movement: its DOFs in `state.u` get
    /// −L_II⁻¹ L_IK·moved.
    ///
    /// # Errors
    /// The backend's failure.
    pub fn finish(
        self,
        condensed: &mut CondensedSystem,
        stats: &mut SolverStats,
        dofs: &DofMap,
        state: &mut State,
    ) -> Result<(), CondensedError> {
        if self.moved.iter().all(|&v| v == 0.0) {
            return Ok(());
        }
        let x = condensed.follow(stats, &self.moved)?;
        for (d, e) in dofs.equation.iter().enumerate() {
            if let Some(e) = *e {
                if !self.kept.contains(e) {
                    state.u[d] += x[e];
                }
            }
        }
        Ok(())
    }
}

/// The elements' part of the internal force at the current displacements, and the residual's
/// round-off floor there.
#[derive(Clone, Copy)]
pub struct BalancedInterior<'a> {
    pub element_force: &'a [f64],
    pub floor: f64,
}

/// An interface iteration from the start of an increment, where the soil is elastic and condensed
/// as it is now, onto the unknowns the interface touches now, and the right-hand side `rhs` is no
/// more than round-off (`balanced.floor`) off the kept unknowns: the interior is in balance as the
/// last increment's end left it (its interior followed the interface), and the increment's load
/// moved the kept unknowns alone (a pulled reinforcement's head).
pub fn start_in_balance(
    condensed: &CondensedSystem,
    system: SystemInputs,
    state: &State,
    rhs: &[f64],
    balanced: BalancedInterior,
) -> Option<Deferred> {
    if system.soil.trial.tangents.iter().any(Option::is_some) {
        return None;
    }
    let (kept, soil_key) = condensed.condensed_on()?;
    if soil_key != system.soil_fingerprint() || **kept != kept_equations(&system) {
        return None;
    }
    if !(kept.interior_norm(rhs) <= balanced.floor) {
        return None;
    }
    Deferred::start(condensed, system.elements, system.dofs, state, balanced)
}

/// An iteration of the interface alone: the kept rows of `rhs` solved with S + C_KK. Returns the
/// correction over all unknowns (zero in the interior) and its residual on the kept system; `None`
/// when the kept system cannot be solved (the caller finishes the deferral and solves in full).
pub fn solve_deferred(
    condensed: &mut CondensedSystem,
    stats: &mut SolverStats,
    deferred: &mut Deferred,
    system: SystemInputs,
    key: u64,
    rhs: &[f64],
) -> Option<(Vec<f64>, f64)> {
    // (the interface's entries assembled only when `key` names a matrix not factorised yet)
    let change = || system.assemble_reinforcement_and_interface();
    let interface = InterfacePart { key, assemble: &change };
    let rhs_kept = deferred.kept.gather(rhs);
    let solved = condensed.solve_kept(stats, deferred.soil_key, &interface, &rhs_kept).ok()?;
    let mut x = vec![0.0; rhs.len()];
    for ((&e, &v), moved) in deferred.kept.equations().iter().zip(&solved.x).zip(deferred.moved.iter_mut()) {
        x[e] = v;
        *moved += v;
    }
    for (soil, change) in deferred.soil_moved.iter_mut().zip(&solved.soil_force) {
        *soil += change;
    }
    Some((x, solved.residual))
}
