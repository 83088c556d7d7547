//! The internal forces (the elements' K_e·u_e, the springs' τ·ℓ·row, the bars' axial forces) and
//! the round-off floor of an out-of-balance force made from them.

use super::block_sum::par_block_sum;
use super::system::{ElementMatrices, SoilView};
use crate::element::bar::BarStates;
use crate::element::soil_state::element_force;
use crate::interface::rows::InterfaceRows;

/// Internal forces over all displacement DOFs: the elements' K_e·u_e plus the springs' τ·ℓ·row (the
/// multipliers' Cᵀλ apart). `taus` holds each spring's shear stress.
pub fn internal_force(
    elements: &ElementMatrices,
    soil: SoilView<'_>,
    rows: &InterfaceRows,
    taus: &[f64],
    bars: &BarStates,
    u: &[f64],
) -> Vec<f64> {
    let mut f = soil_and_bar_force(elements, soil, bars, u);
    add_spring_forces(&mut f, rows, taus);
    f
}

/// The springs' τ·ℓ·row added into `f`.
pub fn add_spring_forces(f: &mut [f64], rows: &InterfaceRows, taus: &[f64]) {
    for (spring, tau) in rows.springs.iter().zip(taus) {
        for &(d, c) in &spring.row {
            f[d] += tau * spring.tributary * c;
        }
    }
}

/// The soil elements' and the bars' part of the internal force: what depends on the displacements,
/// the soil's trial state and the bars' states alone (not on the interface springs).
pub fn soil_and_bar_force(elements: &ElementMatrices, soil: SoilView<'_>, bars: &BarStates, u: &[f64]) -> Vec<f64> {
    let mut f = forces_and_magnitudes(elements, soil, u, false).0;
    add_bar_forces(&mut f, elements, bars, u, None);
    f
}

/// The soil's and the bars' force with the residual's round-off floor, and in a dynamic stage the
/// dynamic operator's part of the force, D·u, on its own.
pub struct ElementForce {
    pub force: Vec<f64>,
    pub floor: f64,
    /// D·u, while a dynamic stage's operator is in place.
    pub operator: Option<Vec<f64>>,
}

/// [`soil_and_bar_force`], the residual's round-off floor and D·u, in one pass over the elements.
///
/// The round-off floor of the out-of-balance force: ‖Σ_e |K_e·u_e|‖ (per DOF, the sum of the
/// magnitudes of the element forces that cancel there) times a few ε. A residual below it cannot be
/// reduced by iterating.
pub fn soil_and_bar_force_and_floor(
    elements: &ElementMatrices,
    soil: SoilView<'_>,
    bars: &BarStates,
    u: &[f64],
) -> ElementForce {
    let (mut force, magnitudes, mut operator) = forces_and_magnitudes(elements, soil, u, true);
    add_bar_forces(&mut force, elements, bars, u, operator.as_deref_mut());
    ElementForce { force, floor: floor_of(&magnitudes), operator }
}

/// The soil elements' part of the internal force, and (with `magnitudes`) per DOF the sum of the
/// magnitudes of the element forces there (the round-off floor's): in the force the soil's K_e·u_e
/// or its stress-carried force (the bars' come from their states: `add_bar_forces`), in the
/// magnitudes every block's |K_e·u_e| terms and the soil's
/// stress-carried forces (reference, Mohr–Coulomb and pore forces); with the magnitudes, in a
/// dynamic stage, the soil's D_e·u_e on their own.
fn forces_and_magnitudes(
    elements: &ElementMatrices,
    soil: SoilView<'_>,
    u: &[f64],
    magnitudes: bool,
) -> (Vec<f64>, Vec<f64>, Option<Vec<f64>>) {
    let n = u.len();
    let first_bar = elements.bars.first().map(|b| b.block).unwrap_or(elements.blocks.len());
    let blocks = if magnitudes { &elements.blocks[..] } else { &elements.blocks[..first_bar] };
    // one sum: the force in the first n entries, the magnitudes in the next n, then D·u
    let operator = magnitudes && elements.inertia.is_some();
    let width = n * (1 + usize::from(magnitudes) + usize::from(operator));
    // cut where the soil's blocks alone are cut: the force is the same to the last bit with or
    // without the magnitudes (the closing check's force is the one a step's results report)
    let mut both = par_block_sum(blocks, first_bar, width, |s, dl, k, f| {
        if s >= first_bar {
            // a bar: its magnitudes here, its force from its state (`add_bar_forces`)
            for (a, &da) in dl.iter().enumerate() {
                for (b, &db) in dl.iter().enumerate() {
                    f[n + da] += (k[(a, b)] * u[db]).abs();
                }
            }
            return;
        }
        let state = &soil.field.elements()[s];
        if !state.active {
            return;
        }
        if let Some(inertia) = &elements.inertia {
            inertia.add_force(s, dl, u, f, magnitudes.then_some(n), operator.then_some(2 * n));
        }
        if magnitudes {
            let forces = [
                state.reference_force.as_ref(),
                state.pore_force.as_ref(),
                soil.trial.forces.get(s).and_then(|f| f.as_ref()),
            ];
            for extra in forces.into_iter().flatten() {
                for (a, &da) in dl.iter().enumerate() {
                    f[n + da] += extra[a].abs();
                }
            }
        }
        if state.placed.is_none() && state.reference_force.is_none() && state.pore_force.is_none() {
            // the common case (elastic soil present from the start): K_e·u_e with no copies
            if !matches!(soil.trial.forces.get(s), Some(Some(_))) {
                for (a, &da) in dl.iter().enumerate() {
                    let mut sum = 0.0;
                    let mut magnitude = 0.0;
                    for (b, &db) in dl.iter().enumerate() {
                        let term = k[(a, b)] * u[db];
                        sum += term;
                        magnitude += term.abs();
                    }
                    f[da] += sum;
                    if magnitudes {
                        f[n + da] += magnitude;
                    }
                }
                return;
            }
        }
        if magnitudes {
            for (a, &da) in dl.iter().enumerate() {
                for (b, &db) in dl.iter().enumerate() {
                    f[n + da] += (k[(a, b)] * u[db]).abs();
                }
            }
        }
        let u_e: Vec<f64> = dl.iter().map(|&d| u[d]).collect();
        let mut fe = vec![0.0; dl.len()];
        element_force(soil.field, soil.trial, s, k, &u_e, &mut fe);
        for (a, &da) in dl.iter().enumerate() {
            f[da] += fe[a];
        }
    });
    let operator = operator.then(|| both.split_off(2 * n));
    let magnitudes = both.split_off(n);
    (both, magnitudes, operator)
}

/// The bars' part of the internal force alone.
pub fn bar_force(elements: &ElementMatrices, bars: &BarStates, u: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; u.len()];
    add_bar_forces(&mut f, elements, bars, u, None);
    f
}

/// The bars' forces added into `f`, and in a dynamic stage their D_e·u_e into `f` and `operator`.
fn add_bar_forces(
    f: &mut [f64],
    elements: &ElementMatrices,
    bars: &BarStates,
    u: &[f64],
    mut operator: Option<&mut [f64]>,
) {
    for (i, bar) in elements.bars.iter().enumerate() {
        let dl = &elements.blocks[bar.block].0;
        // in a dynamic stage, the bar's inertia (its mass's part of D·u)
        if let Some(inertia) = &elements.inertia {
            inertia.add_force(bar.block, dl, u, f, None, None);
            if let Some(operator) = operator.as_deref_mut() {
                inertia.add_force(bar.block, dl, u, operator, None, None);
            }
        }
        let t = bar.force(u, dl, bars, i);
        let e = bar.axis;
        f[dl[0]] -= t * e[0];
        f[dl[1]] -= t * e[1];
        f[dl[2]] += t * e[0];
        f[dl[3]] += t * e[1];
    }
}

/// 64 ε ‖magnitudes‖.
fn floor_of(magnitudes: &[f64]) -> f64 {
    64.0 * f64::EPSILON * magnitudes.iter().map(|v| v * v).sum::<f64>().sqrt()
}
