//! A system whose matrix is a fixed sparse part and a part that changes from one solve to the next
//! but only among a few kept unknowns:
//!
//! ```text
//! A = L + C,   C zero outside the kept rows and columns K
//! ```
//!
//! L is condensed onto K once ([`super::schur`]: one sparse factorisation with the interior
//! eliminated, S = L_KK − L_KI L_II⁻¹ L_IK); each new C costs one dense LU of S + C_KK (or a
//! low-rank update of the last one, when few of its columns changed), and each
//! right-hand side one condensation, one dense solve and one expansion. This is how an interface
//! iteration gets Newton's tangent at the cost of solves: the soil is L, the interface's springs and
//! rows are C.
//!
//! Every solution is checked against A itself (‖Ax − b‖/‖b‖, refined as [`super::linear_system`]
//! does) so a condensed solve is never less accurate than a direct one.

use super::coupled_kept::CoupledKept;
use super::csc::{CscMatrix, PatternCache, Triplets};
use super::dense_update::{FixedPart, SparseColumns, UpdatedLu};
use super::linear_system::SolverStats;
use super::schur::Condensing;
use super::{make_condensing, norm2, Backend, Failure, SolverOptions};
use crate::error::SolveError;
use faer::Mat;
use std::time::Instant;

/// The linear part as last condensed.
struct LinearPart {
    key: u64,
    /// The number of equations.
    n: usize,
    /// L itself, for the residual of a solve of the whole system. Let go once the kept system is
    /// solved alone (at 10⁵ unknowns it is 22 MB beside the factors); a later whole solve checks
    /// its residual with the caller's product of L instead (from the element matrices: a pass over
    /// the elements, where assembling L again sorted millions of entries, at every increment).
    matrix: Option<CscMatrix>,
    /// S: its dense block and its few entries outside it.
    schur: FixedPart,
    /// The kept unknowns, and those of them the interior reaches, which alone the backend
    /// condensed onto.
    coupled: CoupledKept,
}

impl LinearPart {
    /// S.
    fn schur(&self) -> &FixedPart {
        &self.schur
    }
}

/// The dense LU of S + C_KK for one change part (updated, not refactorised, when few columns
/// changed: [`UpdatedLu`], which also holds C_KK, the changing part it was made with: a key may
/// stand for more than one set of values (an iteration matrix kept while the rows' coefficients
/// move), and every solution is checked against the matrix it was solved with).
struct DensePart {
    key: u64,
    lu: UpdatedLu,
    /// The factorisations, updates and iterations of `lu` already added to the run's counts.
    counted: [usize; 3],
}

/// A solve of the kept system alone ([`CondensedSystem::solve_kept`]).
pub struct KeptSolution {
    /// x_K.
    pub x: Vec<f64>,
    /// ‖(S + C_KK)·x_K − r_K‖ / ‖r_K‖.
    pub residual: f64,
    /// S·x_K: the change of the soil's force on the kept unknowns when they move by x_K and the
    /// interior follows in balance.
    pub soil_force: Vec<f64>,
}

pub struct CondensedSystem {
    condensing: Box<dyn Condensing>,
    linear: Option<LinearPart>,
    dense: Option<DensePart>,
    /// Equation → index among the kept unknowns, for the current linear part.
    position: Vec<Option<usize>>,
    /// The linear part whose condensation failed (not tried again).
    failed: Option<(u64, Vec<usize>)>,
}

impl CondensedSystem {
    /// A condensed system on `backend` (MUMPS's Schur complement, or block elimination on the
    /// others).
    ///
    /// # Errors
    /// The backend's error when it cannot be started.
    pub fn new(backend: Backend, options: &SolverOptions) -> Result<Self, SolveError> {
        Ok(CondensedSystem {
            condensing: make_condensing(backend, options)?,
            linear: None,
            dense: None,
            position: Vec::new(),
            failed: None,
        })
    }

    pub fn backend(&self) -> Backend {
        self.condensing.backend()
    }

    /// The kept unknowns and the key of the linear part last condensed.
    pub fn condensed_on(&self) -> Option<(&[usize], u64)> {
        self.linear.as_ref().map(|l| (l.coupled.kept(), l.key))
    }

    /// Whether every entry of `change` lies among `kept` (sorted equations).
    pub fn fits(kept: &[usize], change: &Triplets) -> bool {
        let inside = |&e: &u32| kept.binary_search(&(e as usize)).is_ok();
        change.rows.iter().all(inside) && change.cols.iter().all(inside)
    }

    /// Condense L when `linear_key` (or `kept`) is new, and factorise S + C_KK when `change_key`
    /// is (`change` assembles C only then).
    #[allow(clippy::too_many_arguments)]
    fn prepare(
        &mut self,
        stats: &mut SolverStats,
        n: usize,
        kept: &[usize],
        linear_key: u64,
        linear: &dyn Fn() -> Triplets,
        change_key: u64,
        change: &dyn Fn() -> Triplets,
    ) -> Result<(), Failure> {
        let current = self.linear.as_ref().is_some_and(|l| l.key == linear_key && l.coupled.kept() == kept);
        if !current {
            if self.failed.as_ref().is_some_and(|(k, list)| *k == linear_key && list == kept) {
                return Err(Failure::Singular { equations: Vec::new() });
            }
            // the last condensation, whose factorisation a new L with the same reduced L reuses
            let last = self.linear.take().map(|l| (l.schur, l.coupled));
            self.dense = None;
            let t = Instant::now();
            let triplets = linear();
            // a pattern cache would keep its refill map for the next soil, which comes seldom
            let (matrix, _) = PatternCache::default().assemble(n, &triplets);
            drop(triplets);
            stats.assembly_seconds += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let (schur, coupled, reused) =
                match CoupledKept::condense_onto(self.condensing.as_mut(), &matrix, kept, last) {
                    Ok(s) => s,
                    Err(e) => {
                        self.failed = Some((linear_key, kept.to_vec()));
                        return Err(e);
                    }
                };
            if !reused {
                stats.analyses += 1;
                stats.factorizations += 1;
            }
            stats.factorize_seconds += t.elapsed().as_secs_f64();
            self.position = vec![None; n];
            for (k, &e) in kept.iter().enumerate() {
                self.position[e] = Some(k);
            }
            self.linear = Some(LinearPart { key: linear_key, n, matrix: Some(matrix), schur, coupled });
        }
        let m = kept.len();
        if self.dense.as_ref().is_none_or(|d| d.key != change_key) {
            let t = Instant::now();
            let change = change();
            stats.assembly_seconds += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let mut entries = Vec::with_capacity(change.values.len());
            for ((&i, &j), &v) in change.rows.iter().zip(&change.cols).zip(&change.values) {
                let (Some(i), Some(j)) = (self.position[i as usize], self.position[j as usize]) else {
                    return Err(Failure::Other(SolveError::Backend {
                        backend: self.condensing.backend().name(),
                        message: format!("an entry ({i}, {j}) of the changing part lies outside the kept unknowns"),
                    }));
                };
                entries.push((i, j, v));
            }
            let change = SparseColumns::from_entries(m, entries.into_iter());
            let schur = self.linear.as_ref().expect("set above").schur();
            match self.dense.as_mut() {
                Some(dense) => {
                    dense.lu.set(schur, change);
                    dense.key = change_key;
                }
                None => {
                    let lu = UpdatedLu::new(schur, change);
                    self.dense = Some(DensePart { key: change_key, lu, counted: [0; 3] });
                }
            }
            self.tally(stats);
            stats.dense_seconds += t.elapsed().as_secs_f64();
        }
        Ok(())
    }

    /// Solve (L + C) x = b. `linear` assembles L when `linear_key` (or `kept`) is new; `change_key`
    /// names the iteration matrix: while it stays, the dense factorisation made with the C of its
    /// first solve is reused (and x solves that matrix). Returns x and ‖Ax − b‖/‖b‖ for the matrix
    /// solved with.
    ///
    /// # Errors
    /// The backend's failure (a singular interior is [`Failure::Singular`] with no equations), or
    /// [`Failure::Singular`] when the solution does not meet a relative residual of 1e-6.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        stats: &mut SolverStats,
        n: usize,
        kept: &[usize],
        linear_key: u64,
        linear: &dyn Fn() -> Triplets,
        linear_times: &dyn Fn(&[f64]) -> Vec<f64>,
        change_key: u64,
        change: &Triplets,
        rhs: &[f64],
    ) -> Result<(Vec<f64>, f64), Failure> {
        self.prepare(stats, n, kept, linear_key, linear, change_key, &|| change.clone())?;
        let mut x = self.solve_once(stats, rhs)?;
        let t = Instant::now();
        let mut residual = self.relative_residual(&x, rhs, linear_times);
        for _ in 0..2 {
            if !(residual > 1e-10) || !x.iter().all(|v| v.is_finite()) {
                break;
            }
            let r = self.residual(&x, rhs, linear_times);
            let dx = self.solve_once(stats, &r)?;
            let refined: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
            let refined_residual = self.relative_residual(&refined, rhs, linear_times);
            if refined_residual < residual {
                x = refined;
                residual = refined_residual;
            } else {
                break;
            }
        }
        stats.check_seconds += t.elapsed().as_secs_f64();
        if !x.iter().all(|v| v.is_finite()) || !(residual < 1e-6) {
            return Err(Failure::Singular { equations: Vec::new() });
        }
        stats.max_relative_residual = stats.max_relative_residual.max(residual);
        Ok((x, residual))
    }

    /// Solve (S + C_KK) x_K = r_K on the kept unknowns alone: an iteration whose interior is
    /// already in balance, with L condensed for `linear_key` and the same `kept` as the last
    /// [`CondensedSystem::solve`]. Returns x_K, its relative residual on the kept system, and S·x_K
    /// (the change of the soil's force on the kept unknowns; the residual's check computes it).
    ///
    /// # Errors
    /// [`Failure::Singular`] when the kept system's residual exceeds 1e-6, or when L is not the one
    /// condensed.
    pub fn solve_kept(
        &mut self,
        stats: &mut SolverStats,
        linear_key: u64,
        change_key: u64,
        change: &dyn Fn() -> Triplets,
        rhs_kept: &[f64],
    ) -> Result<KeptSolution, Failure> {
        let Some(linear) = self.linear.as_mut() else { return Err(Failure::Singular { equations: Vec::new() }) };
        if linear.key != linear_key {
            return Err(Failure::Singular { equations: Vec::new() });
        }
        linear.matrix = None;
        let (n, kept) = (linear.n, linear.coupled.kept().to_vec());
        let none = || Triplets::default();
        self.prepare(stats, n, &kept, linear_key, &none, change_key, change)?;
        let t = Instant::now();
        let schur = self.linear.as_ref().expect("checked above").schur();
        let dense = self.dense.as_mut().expect("prepared");
        let m = rhs_kept.len();
        let b = Mat::from_fn(m, 1, |i, _| rhs_kept[i]);
        let y = dense.lu.solve(schur, &b);
        // the true residual b − S·y − C·y, whatever the solve reported: S·y is wanted anyway
        let soil = schur.times(y.as_ref());
        let r = &b - &soil - dense.lu.change().times(y.as_ref());
        let rn = r.norm_l2();
        self.tally(stats);
        let x: Vec<f64> = (0..m).map(|i| y[(i, 0)]).collect();
        let bn = b.norm_l2();
        let residual = if bn > 0.0 { rn / bn } else { rn };
        stats.dense_seconds += t.elapsed().as_secs_f64();
        if !x.iter().all(|v| v.is_finite()) || !(residual < 1e-6) {
            return Err(Failure::Singular { equations: Vec::new() });
        }
        stats.max_relative_residual = stats.max_relative_residual.max(residual);
        Ok(KeptSolution { x, residual, soil_force: (0..m).map(|i| soil[(i, 0)]).collect() })
    }

    /// The diagonal of the linear part L last condensed (every equation); `None` when L has been
    /// let go (an interface iteration solved the kept system alone since).
    pub fn linear_diagonal(&self) -> Option<Vec<f64>> {
        let matrix = self.linear.as_ref()?.matrix.as_ref()?;
        let pattern = &matrix.pattern;
        let mut diagonal = vec![0.0; pattern.n()];
        for (j, d) in diagonal.iter_mut().enumerate() {
            let entries = pattern.col_ptr()[j]..pattern.col_ptr()[j + 1];
            for k in entries {
                if pattern.row_idx()[k] == j {
                    *d += matrix.values[k];
                }
            }
        }
        Some(diagonal)
    }

    /// The whole correction when the kept unknowns moved by `moved` with the interior following in
    /// balance: x_I = −L_II⁻¹ L_IK·moved, x_K = moved. One condensation of nothing and one
    /// expansion.
    ///
    /// # Errors
    /// The backend's failure.
    pub fn follow(&mut self, stats: &mut SolverStats, moved: &[f64]) -> Result<Vec<f64>, Failure> {
        let Some(linear) = self.linear.as_ref() else { return Err(Failure::Singular { equations: Vec::new() }) };
        let zero = vec![0.0; linear.n];
        let t = Instant::now();
        linear.coupled.condense(self.condensing.as_mut(), &zero)?;
        let x = linear.coupled.expand(self.condensing.as_mut(), &zero, moved)?;
        stats.solve_seconds += t.elapsed().as_secs_f64();
        stats.solves += 1;
        Ok(x)
    }

    /// Condense, solve densely, expand.
    fn solve_once(&mut self, stats: &mut SolverStats, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        let t = Instant::now();
        let coupled = &self.linear.as_ref().expect("condensed before").coupled;
        let reduced = coupled.condense(self.condensing.as_mut(), rhs)?;
        stats.solve_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let m = reduced.len();
        let b = Mat::from_fn(m, 1, |i, _| reduced[i]);
        let schur = self.linear.as_ref().expect("condensed before").schur();
        let y = self.dense.as_mut().expect("factorised before").lu.solve(schur, &b);
        self.tally(stats);
        let kept_solution: Vec<f64> = (0..m).map(|i| y[(i, 0)]).collect();
        stats.dense_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let coupled = &self.linear.as_ref().expect("condensed before").coupled;
        let x = coupled.expand(self.condensing.as_mut(), rhs, &kept_solution)?;
        stats.solve_seconds += t.elapsed().as_secs_f64();
        stats.solves += 1;
        Ok(x)
    }

    /// Add the dense part's factorisations, updates and iterations since the last tally to the
    /// run's counts.
    fn tally(&mut self, stats: &mut SolverStats) {
        let Some(dense) = self.dense.as_mut() else { return };
        let now = [dense.lu.factorizations, dense.lu.updates, dense.lu.iterations];
        stats.dense_factorizations += now[0] - dense.counted[0];
        stats.dense_updates += now[1] - dense.counted[1];
        stats.dense_iterations += now[2] - dense.counted[2];
        dense.counted = now;
    }

    /// b − (L + C) x.
    /// b − (L + C)·x, with L's product from its matrix while it is held, from `linear_times`
    /// (the caller's product, from its elements) once it was let go.
    fn residual(&self, x: &[f64], rhs: &[f64], linear_times: &dyn Fn(&[f64]) -> Vec<f64>) -> Vec<f64> {
        let linear = self.linear.as_ref().expect("set before a solve");
        let change = self.dense.as_ref().expect("factorised before a solve").lu.change();
        let mut ax = match linear.matrix.as_ref() {
            Some(matrix) => matrix.mul_vec(x),
            None => linear_times(x),
        };
        let kept = linear.coupled.kept();
        let x_kept = Mat::from_fn(kept.len(), 1, |k, _| x[kept[k]]);
        // C·x on the kept unknowns (L is in the product above)
        let cx = change.times(x_kept.as_ref());
        for (k, &e) in kept.iter().enumerate() {
            ax[e] += cx[(k, 0)];
        }
        rhs.iter().zip(&ax).map(|(b, a)| b - a).collect()
    }

    fn relative_residual(&self, x: &[f64], rhs: &[f64], linear_times: &dyn Fn(&[f64]) -> Vec<f64>) -> f64 {
        let r = norm2(&self.residual(x, rhs, linear_times));
        let b = norm2(rhs);
        if b > 0.0 {
            r / b
        } else {
            r
        }
    }
}

#[cfg(test)]
mod tests {
    //! A whole solve after the kept system was solved alone: L was let go by then and its product
    //! comes from the caller; the solution meets (L + C) x = b to round-off on every backend.
    use super::*;

    /// A chain of 12 springs fixed at one end (L), and a spring between the kept unknowns 3 and 11
    /// (C).
    fn chain() -> (Triplets, Triplets, Vec<usize>) {
        let mut l = Triplets::default();
        for i in 0..12 {
            l.push(i, i, if i == 11 { 1.5 } else { 2.5 });
            if i + 1 < 12 {
                l.push(i, i + 1, -1.0);
                l.push(i + 1, i, -1.0);
            }
        }
        let mut c = Triplets::default();
        for (i, j, v) in [(3, 3, 0.7), (11, 11, 0.7), (3, 11, -0.7), (11, 3, -0.7)] {
            c.push(i, j, v);
        }
        (l, c, vec![3, 8, 11])
    }

    #[test]
    fn a_whole_solve_after_a_kept_one_checks_its_residual_with_the_callers_product() {
        let (l, c, kept) = chain();
        let n = 12;
        let rhs: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64 * 0.61).cos()).collect();
        let (whole, _) = PatternCache::default().assemble(
            n,
            &Triplets {
                rows: l.rows.iter().chain(&c.rows).copied().collect(),
                cols: l.cols.iter().chain(&c.cols).copied().collect(),
                values: l.values.iter().chain(&c.values).copied().collect(),
            },
        );
        let meets = |x: &[f64]| {
            let ax = whole.mul_vec(x);
            ax.iter().zip(&rhs).all(|(a, b)| (a - b).abs() < 1e-12 * b.abs().max(1.0))
        };
        for backend in Backend::available() {
            let mut system = CondensedSystem::new(backend, &SolverOptions::default()).expect("backend starts");
            let mut stats = SolverStats::default();
            let linear = || l.clone();
            let l_matrix = PatternCache::default().assemble(n, &l).0;
            let products = std::cell::Cell::new(0);
            let linear_times = |x: &[f64]| {
                products.set(products.get() + 1);
                l_matrix.mul_vec(x)
            };
            let (x, _) =
                system.solve(&mut stats, n, &kept, 1, &linear, &linear_times, 2, &c, &rhs).expect("first whole solve");
            assert!(meets(&x), "{}: first whole solve", backend.name());
            let rhs_kept: Vec<f64> = kept.iter().map(|&e| rhs[e]).collect();
            system.solve_kept(&mut stats, 1, 2, &|| c.clone(), &rhs_kept).expect("kept solve");
            assert!(system.linear.as_ref().is_some_and(|p| p.matrix.is_none()), "{}: L let go", backend.name());
            assert_eq!(products.get(), 0, "{}: L's own matrix checks the first solve", backend.name());
            let (x, residual) =
                system.solve(&mut stats, n, &kept, 1, &linear, &linear_times, 2, &c, &rhs).expect("second whole solve");
            assert!(meets(&x) && residual < 1e-12, "{}: whole solve after the kept one: {residual}", backend.name());
            assert!(products.get() >= 1, "{}: the caller's product checks the second", backend.name());
            assert!(
                system.linear.as_ref().is_some_and(|p| p.matrix.is_none()),
                "{}: L not assembled again",
                backend.name()
            );
        }
    }
}
