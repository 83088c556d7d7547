//! The inertia and damping in a time step: each element's mass matrix M_e (the soil's and the
//! bars'), the dashpots B_e of the soil's absorbing sides, and the coefficients of the step's
//! dynamic operator D_e = m·M_e + k·K_e + b·B_e (K_e a soil element's elastic stiffness, for the
//! stiffness-proportional part of Rayleigh damping; a bar's D_e is m·M_e alone). While a dynamic
//! stage runs, the assembly adds D_e to every present element's block and D_e·u_e to its internal
//! force, so that a time step is solved as an increment of a static problem (docs/dynamics.md).

use super::block_sum::par_block_sum;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// The elements' masses and dashpots, the dynamic operator's coefficients, and each element's
/// operator D_e made of them; indexed by block (the soil elements first, then the bars).
pub struct Inertia {
    /// Each block's mass matrix (zero for an element not present).
    pub masses: Vec<DMatrix<f64>>,
    /// Each soil element's dashpots on its absorbing sides, if it has any (Lysmer–Kuhlemeyer).
    pub dashpots: Vec<Option<DMatrix<f64>>>,
    /// Whether any soil element has dashpots.
    any_dashpot: bool,
    /// Whether each block's element is present in the stage.
    present: Vec<bool>,
    /// How many of the blocks are soil elements (the rest are bars).
    soil: usize,
    /// The assembled M's diagonal over all displacement DOFs when every present element's mass is
    /// lumped (diagonal): M·x is then a product by DOF.
    lumped: Option<Vec<f64>>,
    /// Each block's D_e for the coefficients below (empty before they are set).
    operators: Vec<DMatrix<f64>>,
    /// m, the coefficient of M_e in D_e.
    mass: f64,
    /// k, the coefficient of a soil element's elastic K_e in D_e.
    stiffness: f64,
    /// b, the coefficient of the dashpots B_e in D_e.
    damper: f64,
    /// Tells one set of masses from another (a fingerprint of the assembled matrix takes it).
    generation: u64,
}

impl Inertia {
    /// The `masses` of every block (`blocks`, for their DOFs: the first `dashpots.len()` are the
    /// soil's) and the soil's `dashpots`, of the elements `present`, as generation `generation`;
    /// D = 0 until [`Inertia::set_coefficients`].
    pub fn new(
        mut masses: Vec<DMatrix<f64>>,
        dashpots: Vec<Option<DMatrix<f64>>>,
        present: Vec<bool>,
        generation: u64,
        blocks: &[(Vec<usize>, DMatrix<f64>)],
        dofs: usize,
    ) -> Inertia {
        let soil = dashpots.len();
        // (an element not present has no mass: a bar not yet placed is in the matrix's pattern)
        for (mass, _) in masses.iter_mut().zip(&present).filter(|(_, &p)| !p) {
            mass.fill(0.0);
        }
        let present_blocks = || (0..masses.len()).filter(|&b| present[b]);
        let diagonal = |m: &DMatrix<f64>| (0..m.nrows()).all(|a| (0..m.ncols()).all(|c| a == c || m[(a, c)] == 0.0));
        let lumped = present_blocks().all(|b| diagonal(&masses[b])).then(|| {
            let mut d = vec![0.0; dofs];
            for b in present_blocks() {
                for (a, &da) in blocks[b].0.iter().enumerate() {
                    d[da] += masses[b][(a, a)];
                }
            }
            d
        });
        Inertia {
            masses,
            any_dashpot: dashpots.iter().any(Option::is_some),
            dashpots,
            present,
            soil,
            lumped,
            operators: Vec::new(),
            mass: 0.0,
            stiffness: 0.0,
            damper: 0.0,
            generation,
        }
    }

    /// D_e = m·M_e + k·K_e + b·B_e of every soil element and m·M_e of every bar (`blocks`: the
    /// elements' elastic blocks), made again only when a coefficient changed (a time step of
    /// another length).
    pub fn set_coefficients(&mut self, (m, k, b): (f64, f64, f64), blocks: &[(Vec<usize>, DMatrix<f64>)]) {
        if !self.operators.is_empty() && (m, k, b) == (self.mass, self.stiffness, self.damper) {
            return;
        }
        (self.mass, self.stiffness, self.damper) = (m, k, b);
        let soil = self.soil;
        self.operators = self
            .masses
            .par_iter()
            .zip(blocks)
            .enumerate()
            .map(|(e, (mass, (_, elastic)))| {
                if e >= soil {
                    return mass * m;
                }
                let mut d = mass * m + elastic * k;
                if let Some(dashpot) = &self.dashpots[e] {
                    d += dashpot * b;
                }
                d
            })
            .collect();
    }

    /// D_e's entry (a, c) of block `e`.
    pub fn entry(&self, e: usize, a: usize, c: usize) -> f64 {
        self.operators.get(e).map_or(0.0, |d| d[(a, c)])
    }

    /// D_e·u_e of block `e` (DOFs `dl`) added into `f`; with `magnitudes` (the part of `f` from
    /// there on) the magnitudes of its terms, and with `operator` D_e·u_e again (from there on).
    pub fn add_force(
        &self,
        e: usize,
        dl: &[usize],
        u: &[f64],
        f: &mut [f64],
        magnitudes: Option<usize>,
        operator: Option<usize>,
    ) {
        let Some(d) = self.operators.get(e) else { return };
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
            if let Some(n) = operator {
                f[n + da] += sum[a];
            }
        }
    }

    /// Whether any soil element has dashpots (B ≠ 0).
    pub fn has_dashpots(&self) -> bool {
        self.any_dashpot
    }

    /// A hash of what D is made of: the masses' and dashpots' generation and the three
    /// coefficients.
    pub fn key(&self) -> (u64, u64, u64, u64) {
        (self.generation, self.mass.to_bits(), self.stiffness.to_bits(), self.damper.to_bits())
    }

    /// M·x over all displacement DOFs (`blocks`: the elements', for their DOFs).
    pub fn mass_times(&self, blocks: &[(Vec<usize>, DMatrix<f64>)], x: &[f64]) -> Vec<f64> {
        if let Some(diagonal) = &self.lumped {
            return diagonal.iter().zip(x).map(|(m, x)| m * x).collect();
        }
        let count = self.masses.len();
        par_block_sum(&blocks[..count], count, x.len(), |e, dl, _, y| {
            if self.present[e] {
                add_product(&self.masses[e], dl, x, y);
            }
        })
    }

    /// M·x + k·K·w + B·w over all displacement DOFs, in one pass over the present elements: their
    /// masses (or the lumped diagonal, by DOF), the soil's elastic stiffness (`blocks`, the
    /// stiffness-proportional damping's K) and dashpots.
    pub fn damping_times(&self, blocks: &[(Vec<usize>, DMatrix<f64>)], x: &[f64], k: f64, w: &[f64]) -> Vec<f64> {
        let Inertia { masses, dashpots, any_dashpot, present, soil, lumped, .. } = self;
        if let (Some(diagonal), 0.0, false) = (lumped, k, *any_dashpot) {
            return diagonal.iter().zip(x).map(|(m, x)| m * x).collect();
        }
        let count = masses.len();
        let mut f = par_block_sum(&blocks[..count], count, x.len(), |e, dl, stiffness, y| {
            if !present[e] {
                return;
            }
            if lumped.is_none() {
                add_product(&masses[e], dl, x, y);
            }
            if e >= *soil {
                return;
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
            if let Some(b) = &dashpots[e] {
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
