//! The soil's inertia and damping in a time step: each element's mass matrix M_e, the dashpots B_e
//! of its absorbing sides, and the coefficients of the step's dynamic operator
//! D_e = m·M_e + k·K_e + b·B_e (K_e the element's elastic stiffness, for the stiffness-proportional
//! part of Rayleigh damping). While a dynamic stage runs,
//! the assembly adds D_e to every present soil element's block and D_e·u_e to its internal force,
//! so that a time step is solved as an increment of a static problem (docs/dynamics.md).

use super::block_sum::par_block_sum;
use crate::element::soil_state::SoilField;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// The soil elements' masses and dashpots, the dynamic operator's coefficients, and each
/// element's operator D_e made of them.
pub struct Inertia {
    /// Each soil element's mass matrix, in mesh order.
    pub masses: Vec<DMatrix<f64>>,
    /// Each soil element's dashpots on its absorbing sides, if it has any (Lysmer–Kuhlemeyer).
    pub dashpots: Vec<Option<DMatrix<f64>>>,
    /// The assembled M's diagonal over all displacement DOFs when every present element's mass is
    /// lumped (diagonal): M·x is then a product by DOF.
    lumped: Option<Vec<f64>>,
    /// Each soil element's D_e for the coefficients below (empty before they are set).
    operators: Vec<DMatrix<f64>>,
    /// m, the coefficient of M_e in D_e.
    mass: f64,
    /// k, the coefficient of the elastic K_e in D_e.
    stiffness: f64,
    /// b, the coefficient of the dashpots B_e in D_e.
    damper: f64,
    /// Tells one set of masses from another (a fingerprint of the assembled matrix takes it).
    generation: u64,
}

impl Inertia {
    /// The masses and `dashpots` of the soil present in `field` (`blocks`: the soil's blocks, for
    /// their DOFs), as generation `generation`; D = 0 until [`Inertia::set_coefficients`].
    pub fn new(
        masses: Vec<DMatrix<f64>>,
        dashpots: Vec<Option<DMatrix<f64>>>,
        generation: u64,
        blocks: &[(Vec<usize>, DMatrix<f64>)],
        field: &SoilField,
        dofs: usize,
    ) -> Inertia {
        let present = |s: &usize| field.elements()[*s].active;
        let diagonal = |m: &DMatrix<f64>| (0..m.nrows()).all(|a| (0..m.ncols()).all(|c| a == c || m[(a, c)] == 0.0));
        let lumped = (0..masses.len()).filter(present).all(|s| diagonal(&masses[s])).then(|| {
            let mut d = vec![0.0; dofs];
            for s in (0..masses.len()).filter(present) {
                for (a, &da) in blocks[s].0.iter().enumerate() {
                    d[da] += masses[s][(a, a)];
                }
            }
            d
        });
        Inertia { masses, dashpots, lumped, operators: Vec::new(), mass: 0.0, stiffness: 0.0, damper: 0.0, generation }
    }

    /// D_e = m·M_e + k·K_e + b·B_e of every soil element (`blocks`: the soil's elastic blocks),
    /// made again only when a coefficient changed (a time step of another length).
    pub fn set_coefficients(&mut self, (m, k, b): (f64, f64, f64), blocks: &[(Vec<usize>, DMatrix<f64>)]) {
        if !self.operators.is_empty() && (m, k, b) == (self.mass, self.stiffness, self.damper) {
            return;
        }
        (self.mass, self.stiffness, self.damper) = (m, k, b);
        self.operators = self
            .masses
            .par_iter()
            .zip(&self.dashpots)
            .zip(blocks)
            .map(|((mass, dashpot), (_, elastic))| {
                let mut d = mass * m + elastic * k;
                if let Some(dashpot) = dashpot {
                    d += dashpot * b;
                }
                d
            })
            .collect();
    }

    /// D_e's entry (a, c) of soil element `s`.
    pub fn entry(&self, s: usize, a: usize, c: usize) -> f64 {
        self.operators.get(s).map_or(0.0, |d| d[(a, c)])
    }

    /// D_e·u_e of soil element `s` (DOFs `dl`) added into `f`, and, with `magnitudes` (the second
    /// half of `f`, from `n` on), the magnitudes of its terms.
    pub fn add_force(&self, s: usize, dl: &[usize], u: &[f64], f: &mut [f64], magnitudes: Option<usize>) {
        let Some(d) = self.operators.get(s) else { return };
        // (by columns, as the matrices are stored; at most 16 DOFs to an element, a quad8's)
        let n = dl.len();
        debug_assert!(n <= 18);
        let dd = d.as_slice();
        let (mut sum, mut magnitude) = ([0.0; 18], [0.0; 18]);
        for (c, &dc) in dl.iter().enumerate() {
            let uc = u[dc];
            for a in 0..n {
                let term = dd[c * n + a] * uc;
                sum[a] += term;
                magnitude[a] += term.abs();
            }
        }
        for (a, &da) in dl.iter().enumerate() {
            f[da] += sum[a];
            if let Some(n) = magnitudes {
                f[n + da] += magnitude[a];
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
    let soil = field.elements().len();
    par_block_sum(&blocks[..soil], soil, x.len(), |s, dl, _, y| {
        if field.elements()[s].active {
            add_product(&masses[s], dl, x, y);
        }
    })
}

/// M·x + k·K·w + B·w over all displacement DOFs, in one pass over the present soil elements: their
/// masses (or the lumped diagonal, by DOF), elastic stiffness (`blocks`, the stiffness-proportional
/// damping's K) and dashpots.
pub fn damping_times(
    inertia: &Inertia,
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    field: &SoilField,
    x: &[f64],
    k: f64,
    w: &[f64],
) -> Vec<f64> {
    let Inertia { masses, dashpots, lumped, .. } = inertia;
    let soil = field.elements().len();
    let any_dashpot = dashpots.iter().any(Option::is_some);
    if let (Some(diagonal), 0.0, false) = (lumped, k, any_dashpot) {
        return diagonal.iter().zip(x).map(|(m, x)| m * x).collect();
    }
    let mut f = par_block_sum(&blocks[..soil], soil, x.len(), |s, dl, stiffness, y| {
        if !field.elements()[s].active {
            return;
        }
        if lumped.is_none() {
            add_product(&masses[s], dl, x, y);
        }
        if k != 0.0 {
            let n = dl.len();
            let kk = stiffness.as_slice();
            for (c, &dc) in dl.iter().enumerate() {
                let wc = k * w[dc];
                for (a, &da) in dl.iter().enumerate() {
                    y[da] += kk[c * n + a] * wc;
                }
            }
        }
        if let Some(b) = &dashpots[s] {
            add_product(b, dl, w, y);
        }
    });
    if let Some(diagonal) = lumped {
        for ((f, m), x) in f.iter_mut().zip(diagonal).zip(x) {
            *f += m * x;
        }
    }
    f
}

/// m·x of one element (DOFs `dl`) added into `y`.
fn add_product(m: &DMatrix<f64>, dl: &[usize], x: &[f64], y: &mut [f64]) {
    // (column by column: the matrix is stored by columns)
    let n = dl.len();
    let mm = m.as_slice();
    for (c, &dc) in dl.iter().enumerate() {
        let xc = x[dc];
        if xc != 0.0 {
            for (a, &da) in dl.iter().enumerate() {
                y[da] += mm[c * n + a] * xc;
            }
        }
    }
}
