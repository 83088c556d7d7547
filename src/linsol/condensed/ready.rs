//! A condensed soil with the interface system factorised on it: the state in which a solve can
//! run. [`Ready`] exists only once both are in place, so nothing in a solve asks whether they are.

use super::condensing::Condensing;
use super::coupled::CoupledKept;
use super::fallback::{CondensedError, Fallback};
use super::kept::KeptUnknowns;
use super::kept_matrix::{SoilSchur, SparseColumns};
use super::parts::{InterfacePart, KeptSolution};
use super::updated_lu::UpdatedLu;
use crate::linsol::csc::CscMatrix;
use crate::linsol::linear_system::SolverStats;
use crate::linsol::refine::{accepted, refine, Refinable};
use faer::Mat;
use std::rc::Rc;
use std::time::Instant;

/// The soil L as condensed, and the interface system's factorisation on it.
pub(super) struct CondensedSoil {
    pub key: u64,
    pub kept: Rc<KeptUnknowns>,
    /// L itself, for the residual of a solve of the whole system. Let go once the kept system is
    /// solved alone (at 10⁵ unknowns it is 22 MB beside the factors); a later whole solve checks
    /// its residual with the caller's product of L instead (from the element matrices: a pass over
    /// the elements, where assembling L again sorted millions of entries, at every increment).
    pub matrix: Option<CscMatrix>,
    /// S: its dense block and its few entries outside it.
    pub schur: SoilSchur,
    /// The kept unknowns the interior reaches, which alone the backend condensed onto.
    pub coupled: CoupledKept,
    /// The factorisation of S + C_KK for the last interface part; made again on a new soil.
    pub interface: Option<InterfaceLu>,
}

/// The dense LU of S + C_KK for one interface part (updated, not refactorised, when few columns
/// changed: [`UpdatedLu`], which also holds C_KK, the changing part it was made with: a key may
/// stand for more than one set of values (an iteration matrix kept while the rows' coefficients
/// move), and every solution is checked against the matrix it was solved with).
pub(super) struct InterfaceLu {
    key: u64,
    lu: UpdatedLu,
    /// The factorisations, updates and iterations of `lu` already added to the run's counts, and
    /// the seconds of its factorisations and iterations.
    counted: [usize; 3],
    counted_seconds: [f64; 2],
}

/// A condensed soil and the interface system's factorisation on it, with the run's counts and
/// the caller's product of L: what a solve needs.
pub(super) struct Ready<'a> {
    condensing: &'a mut dyn Condensing,
    kept: &'a KeptUnknowns,
    matrix: Option<&'a CscMatrix>,
    schur: &'a SoilSchur,
    coupled: &'a CoupledKept,
    interface: &'a mut InterfaceLu,
    stats: &'a mut SolverStats,
    linear_times: &'a dyn Fn(&[f64]) -> Vec<f64>,
}

impl<'a> Ready<'a> {
    /// Factorise S + C_KK when `interface.key` is new (C assembled only then).
    ///
    /// # Errors
    /// The equations (row, column) of an entry of C outside the kept unknowns.
    pub fn prepare(
        condensing: &'a mut dyn Condensing,
        soil: &'a mut CondensedSoil,
        stats: &'a mut SolverStats,
        interface: &InterfacePart,
        linear_times: &'a dyn Fn(&[f64]) -> Vec<f64>,
    ) -> Result<Ready<'a>, (u32, u32)> {
        let CondensedSoil { kept, matrix, schur, coupled, interface: lu, .. } = soil;
        let made = match lu.take() {
            Some(current) if current.key == interface.key => current,
            last => {
                let t = Instant::now();
                let change = (interface.assemble)();
                stats.assembly_seconds += t.elapsed().as_secs_f64();
                let t = Instant::now();
                let mut entries = Vec::with_capacity(change.values.len());
                for ((&i, &j), &v) in change.rows.iter().zip(&change.cols).zip(&change.values) {
                    let (Some(p), Some(q)) = (kept.position(i as usize), kept.position(j as usize)) else {
                        *lu = last;
                        return Err((i, j));
                    };
                    entries.push((p, q, v));
                }
                let change = SparseColumns::from_entries(kept.len(), entries.into_iter());
                let mut made = match last {
                    Some(mut dense) => {
                        dense.lu.set(schur, change);
                        dense.key = interface.key;
                        dense
                    }
                    None => InterfaceLu {
                        key: interface.key,
                        lu: UpdatedLu::new(schur, change),
                        counted: [0; 3],
                        counted_seconds: [0.0; 2],
                    },
                };
                tally(&mut made, stats);
                stats.dense_seconds += t.elapsed().as_secs_f64();
                made
            }
        };
        let interface = lu.insert(made);
        Ok(Ready { condensing, kept, matrix: matrix.as_ref(), schur, coupled, interface, stats, linear_times })
    }

    /// (L + C) x = b, refined and checked against L + C.
    pub fn solve(&mut self, rhs: &[f64]) -> Result<(Vec<f64>, f64), CondensedError> {
        let x = self.solve_once(rhs)?;
        let t = Instant::now();
        let (x, residual) = refine(self, x, rhs)?;
        self.stats.check_seconds += t.elapsed().as_secs_f64();
        if !accepted(&x, residual) {
            return Err(Fallback::Inaccurate { residual }.into());
        }
        self.stats.max_relative_residual = self.stats.max_relative_residual.max(residual);
        Ok((x, residual))
    }

    /// (S + C_KK) x_K = r_K, checked against S + C_KK.
    pub fn solve_kept(&mut self, rhs_kept: &[f64]) -> Result<KeptSolution, CondensedError> {
        let t = Instant::now();
        let m = rhs_kept.len();
        let b = Mat::from_fn(m, 1, |i, _| rhs_kept[i]);
        let y = self.interface.lu.solve(self.schur, &b);
        // the true residual b − S·y − C·y, whatever the solve reported: S·y is wanted anyway
        let soil = self.schur.times(y.as_ref());
        let r = &b - &soil - self.interface.lu.change().times(y.as_ref());
        let rn = r.norm_l2();
        tally(self.interface, self.stats);
        let x: Vec<f64> = (0..m).map(|i| y[(i, 0)]).collect();
        let bn = b.norm_l2();
        let residual = if bn > 0.0 { rn / bn } else { rn };
        self.stats.dense_seconds += t.elapsed().as_secs_f64();
        if !accepted(&x, residual) {
            return Err(Fallback::KeptInaccurate { residual }.into());
        }
        self.stats.max_relative_residual = self.stats.max_relative_residual.max(residual);
        Ok(KeptSolution { x, residual, soil_force: (0..m).map(|i| soil[(i, 0)]).collect() })
    }

    /// Condense, solve densely, expand.
    fn solve_once(&mut self, rhs: &[f64]) -> Result<Vec<f64>, CondensedError> {
        let t = Instant::now();
        let reduced = self.coupled.condense(self.condensing, rhs)?;
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let m = reduced.len();
        let b = Mat::from_fn(m, 1, |i, _| reduced[i]);
        let y = self.interface.lu.solve(self.schur, &b);
        tally(self.interface, self.stats);
        let kept_solution: Vec<f64> = (0..m).map(|i| y[(i, 0)]).collect();
        self.stats.dense_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let x = self.coupled.expand(self.condensing, rhs, &kept_solution)?;
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        self.stats.solves += 1;
        Ok(x)
    }
}

impl Refinable for Ready<'_> {
    type Error = CondensedError;

    /// b − (L + C)·x, with L's product from its matrix while it is held, from the caller's
    /// product (from its elements) once it was let go.
    fn residual(&self, x: &[f64], rhs: &[f64]) -> Vec<f64> {
        let mut ax = match self.matrix {
            Some(matrix) => matrix.mul_vec(x),
            None => (self.linear_times)(x),
        };
        let kept = self.kept.equations();
        let x_kept = Mat::from_fn(kept.len(), 1, |k, _| x[kept[k]]);
        // C·x on the kept unknowns (L is in the product above)
        let cx = self.interface.lu.change().times(x_kept.as_ref());
        for (k, &e) in kept.iter().enumerate() {
            ax[e] += cx[(k, 0)];
        }
        rhs.iter().zip(&ax).map(|(b, a)| b - a).collect()
    }

    fn correct(&mut self, r: &[f64]) -> Result<Vec<f64>, CondensedError> {
        self.solve_once(r)
    }
}

/// Add the interface factorisation's factorisations, updates and iterations since the last tally,
/// and their times, to the run's counts.
fn tally(interface: &mut InterfaceLu, stats: &mut SolverStats) {
    let now = [interface.lu.factorizations, interface.lu.updates, interface.lu.iterations];
    stats.dense_factorizations += now[0] - interface.counted[0];
    stats.dense_updates += now[1] - interface.counted[1];
    stats.dense_iterations += now[2] - interface.counted[2];
    interface.counted = now;
    let seconds = [interface.lu.factorization_seconds, interface.lu.iteration_seconds];
    stats.dense_factorization_seconds += seconds[0] - interface.counted_seconds[0];
    stats.dense_iteration_seconds += seconds[1] - interface.counted_seconds[1];
    interface.counted_seconds = seconds;
}
