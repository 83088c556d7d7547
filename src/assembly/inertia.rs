//! The soil's inertia and damping in a time step: each element's mass matrix M_e, the dashpots B_e
//! of its absorbing sides, and the coefficients of the step's dynamic operator
//! D_e = m·M_e + k·K_e + b·B_e (K_e the element's elastic stiffness, for the stiffness-proportional
//! part of Rayleigh damping). While a dynamic stage runs,
//! the assembly adds D_e to every present soil element's block and D_e·u_e to its internal force,
//! so that a time step is solved as an increment of a static problem (docs/dynamics.md).

use super::block_sum::par_block_sum;
use crate::element::soil_state::SoilField;
use nalgebra::DMatrix;

/// The soil elements' masses and the dynamic operator's coefficients.
pub struct Inertia {
    /// Each soil element's mass matrix, in mesh order.
    pub masses: Vec<DMatrix<f64>>,
    /// Each soil element's dashpots on its absorbing sides, if it has any (Lysmer–Kuhlemeyer).
    pub dashpots: Vec<Option<DMatrix<f64>>>,
    /// m, the coefficient of M_e in D_e.
    pub mass: f64,
    /// k, the coefficient of the elastic K_e in D_e.
    pub stiffness: f64,
    /// b, the coefficient of the dashpots B_e in D_e.
    pub damper: f64,
    /// Tells one set of masses from another (a fingerprint of the assembled matrix takes it).
    pub generation: u64,
}

impl Inertia {
    /// D_e's entry (a, c) of soil element `s`, whose elastic stiffness is `k`.
    pub fn entry(&self, s: usize, k: &DMatrix<f64>, a: usize, c: usize) -> f64 {
        let dashpot = self.dashpots[s].as_ref().map_or(0.0, |b| self.damper * b[(a, c)]);
        self.mass * self.masses[s][(a, c)] + self.stiffness * k[(a, c)] + dashpot
    }

    /// D_e·u_e of soil element `s` (elastic stiffness `k`, DOFs `dl`) added into `f`, and, with
    /// `magnitudes` (the second half of `f`, from `n` on), the magnitudes of its terms.
    pub fn add_force(
        &self,
        s: usize,
        k: &DMatrix<f64>,
        dl: &[usize],
        u: &[f64],
        f: &mut [f64],
        magnitudes: Option<usize>,
    ) {
        for (a, &da) in dl.iter().enumerate() {
            let (mut sum, mut magnitude) = (0.0, 0.0);
            for (c, &dc) in dl.iter().enumerate() {
                let term = self.entry(s, k, a, c) * u[dc];
                sum += term;
                magnitude += term.abs();
            }
            f[da] += sum;
            if let Some(n) = magnitudes {
                f[n + da] += magnitude;
            }
        }
    }

    /// A hash of what D is made of: the masses' and dashpots' generation and the three
    /// coefficients.
    pub fn key(&self) -> (u64, u64, u64, u64) {
        (self.generation, self.mass.to_bits(), self.stiffness.to_bits(), self.damper.to_bits())
    }
}

/// M·x over all displacement DOFs: the present soil elements' masses (`blocks`: the soil blocks,
/// for their DOFs).
pub fn mass_times(
    masses: &[DMatrix<f64>],
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    field: &SoilField,
    x: &[f64],
) -> Vec<f64> {
    block_times(blocks, field, x, Some(masses))
}

/// K·x over all displacement DOFs: the present soil elements' elastic stiffness (the
/// stiffness-proportional damping's K).
pub fn stiffness_times(blocks: &[(Vec<usize>, DMatrix<f64>)], field: &SoilField, x: &[f64]) -> Vec<f64> {
    block_times(blocks, field, x, None)
}

/// B·x over all displacement DOFs: the dashpots of the present soil elements' absorbing sides.
pub fn dashpots_times(
    dashpots: &[Option<DMatrix<f64>>],
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    field: &SoilField,
    x: &[f64],
) -> Vec<f64> {
    let soil = field.elements().len();
    par_block_sum(&blocks[..soil], soil, x.len(), |s, dl, _, y| {
        if let (true, Some(b)) = (field.elements()[s].active, &dashpots[s]) {
            add_product(b, dl, x, y);
        }
    })
}

/// The masses' (`Some`) or the elastic blocks' product with `x`.
fn block_times(
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    field: &SoilField,
    x: &[f64],
    masses: Option<&[DMatrix<f64>]>,
) -> Vec<f64> {
    let soil = field.elements().len();
    par_block_sum(&blocks[..soil], soil, x.len(), |s, dl, k, y| {
        if field.elements()[s].active {
            add_product(masses.map_or(k, |masses| &masses[s]), dl, x, y);
        }
    })
}

/// m·x of one element (DOFs `dl`) added into `y`.
fn add_product(m: &DMatrix<f64>, dl: &[usize], x: &[f64], y: &mut [f64]) {
    for (a, &da) in dl.iter().enumerate() {
        y[da] += dl.iter().enumerate().map(|(c, &dc)| m[(a, c)] * x[dc]).sum::<f64>();
    }
}
