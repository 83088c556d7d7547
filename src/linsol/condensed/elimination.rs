//! The Schur complement of a sparse matrix on a set of kept unknowns:
//!
//! ```text
//! A = [ A_II  A_IK ]      S = A_KK − A_KI A_II⁻¹ A_IK
//!     [ A_KI  A_KK ]
//! ```
//!
//! with the interior unknowns I factorised once and the kept unknowns K left as a small dense
//! matrix. A right-hand side is *condensed* onto K (r̃ = r_K − A_KI A_II⁻¹ r_I) and a solution on K
//! *expanded* to all unknowns (x_I = A_II⁻¹ (r_I − A_IK x_K)).
//!
//! MUMPS computes S during its factorisation (ICNTL(19)) and condenses and expands with one
//! forward and one backward pass (ICNTL(26)); every other backend gets [`BlockElimination`]: A_II
//! factorised by the backend itself and S built one column of A_IK at a time.

use super::condensing::Condensing;
use crate::error::SolveError;
use crate::linsol::csc::{CscMatrix, PatternCache, Triplets};
use crate::linsol::{make, Backend, Failure, LinearSolver, SolverOptions};

/// The Schur complement by block elimination: A_II factorised by any backend, S built column by
/// column (one solve per kept unknown that A_IK couples to the interior).
pub struct BlockElimination {
    solver: Box<dyn LinearSolver>,
    n: usize,
    /// Equation → its place among the interior or the kept unknowns.
    place: Vec<Place>,
    interior_count: usize,
    kept_count: usize,
    /// A_IK and A_KI by kept column / kept row: (interior index, value).
    interior_of_kept_column: Vec<Vec<(usize, f64)>>,
    interior_of_kept_row: Vec<Vec<(usize, f64)>>,
    patterns: PatternCache,
}

#[derive(Clone, Copy)]
enum Place {
    Interior(usize),
    Kept(usize),
}

impl BlockElimination {
    pub fn new(solver: Box<dyn LinearSolver>) -> Self {
        BlockElimination {
            solver,
            n: 0,
            place: Vec::new(),
            interior_count: 0,
            kept_count: 0,
            interior_of_kept_column: Vec::new(),
            interior_of_kept_row: Vec::new(),
            patterns: PatternCache::default(),
        }
    }

    fn interior_solve(&mut self, r: Vec<f64>) -> Result<Vec<f64>, Failure> {
        if self.interior_count == 0 {
            return Ok(r);
        }
        self.solver.solve(&r)
    }
}

impl Condensing for BlockElimination {
    fn backend(&self) -> Backend {
        self.solver.backend()
    }

    fn factorize_condensed(&mut self, matrix: &CscMatrix, kept: &[usize]) -> Result<Vec<f64>, Failure> {
        let p = &matrix.pattern;
        let n = p.n();
        let mut place = vec![Place::Interior(0); n];
        for (k, &e) in kept.iter().enumerate() {
            place[e] = Place::Kept(k);
        }
        let mut interior_count = 0;
        for slot in place.iter_mut() {
            if let Place::Interior(i) = slot {
                *i = interior_count;
                interior_count += 1;
            }
        }
        let m = kept.len();
        let mut schur = vec![0.0; m * m];
        let mut interior = Triplets::default();
        let mut column = vec![Vec::new(); m];
        let mut row = vec![Vec::new(); m];
        for j in 0..n {
            for k in p.col_ptr()[j]..p.col_ptr()[j + 1] {
                let (i, v) = (p.row_idx()[k], matrix.values[k]);
                match (place[i], place[j]) {
                    (Place::Interior(a), Place::Interior(b)) => interior.push(a, b, v),
                    (Place::Interior(a), Place::Kept(b)) => column[b].push((a, v)),
                    (Place::Kept(a), Place::Interior(b)) => row[a].push((b, v)),
                    (Place::Kept(a), Place::Kept(b)) => schur[a * m + b] += v,
                }
            }
        }
        self.n = n;
        self.place = place;
        self.interior_count = interior_count;
        self.kept_count = m;
        self.interior_of_kept_column = column;
        self.interior_of_kept_row = row;
        if interior_count == 0 {
            return Ok(schur);
        }
        let (a_ii, new_pattern) = self.patterns.assemble(interior_count, &interior);
        if new_pattern {
            self.solver.analyse(&a_ii)?;
        }
        self.solver.factorize(&a_ii).map_err(|e| match e {
            // the interior's equation numbers mean nothing to the caller
            Failure::Singular { .. } => Failure::Singular { equations: Vec::new() },
            other => other,
        })?;
        for b in 0..m {
            if self.interior_of_kept_column[b].is_empty() {
                continue;
            }
            let mut rhs = vec![0.0; interior_count];
            for &(a, v) in &self.interior_of_kept_column[b] {
                rhs[a] = v;
            }
            let w = self.solver.solve(&rhs)?;
            for a in 0..m {
                let s: f64 = self.interior_of_kept_row[a].iter().map(|&(i, v)| v * w[i]).sum();
                schur[a * m + b] -= s;
            }
        }
        Ok(schur)
    }

    fn condense(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        let (r_interior, mut r_kept) = split(&self.place, self.interior_count, self.kept_count, rhs);
        if self.interior_count > 0 {
            let y = self.interior_solve(r_interior)?;
            for (a, r) in r_kept.iter_mut().enumerate() {
                *r -= self.interior_of_kept_row[a].iter().map(|&(i, v)| v * y[i]).sum::<f64>();
            }
        }
        Ok(r_kept)
    }

    fn expand(&mut self, rhs: &[f64], kept_solution: &[f64]) -> Result<Vec<f64>, Failure> {
        let (mut r_interior, _) = split(&self.place, self.interior_count, self.kept_count, rhs);
        for (b, &x) in kept_solution.iter().enumerate() {
            for &(a, v) in &self.interior_of_kept_column[b] {
                r_interior[a] -= v * x;
            }
        }
        let x_interior = self.interior_solve(r_interior)?;
        let mut x = vec![0.0; self.n];
        for (e, place) in self.place.iter().enumerate() {
            x[e] = match *place {
                Place::Interior(i) => x_interior[i],
                Place::Kept(k) => kept_solution[k],
            };
        }
        Ok(x)
    }
}

fn split(place: &[Place], interior: usize, kept: usize, rhs: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut r_interior = vec![0.0; interior];
    let mut r_kept = vec![0.0; kept];
    for (e, p) in place.iter().enumerate() {
        match *p {
            Place::Interior(i) => r_interior[i] = rhs[e],
            Place::Kept(k) => r_kept[k] = rhs[e],
        }
    }
    (r_interior, r_kept)
}

/// A condensing backend for `backend`: MUMPS's own Schur complement where MUMPS is built in (the
/// sequential build), block elimination over the backend's factorisation otherwise.
///
/// # Errors
/// The backend's own error when it cannot be started.
pub(super) fn make_condensing(backend: Backend, options: &SolverOptions) -> Result<Box<dyn Condensing>, SolveError> {
    match backend.resolve() {
        #[cfg(all(geoslip_mumps, not(feature = "mpi")))]
        Backend::Mumps => Ok(Box::new(crate::linsol::native::mumps::Mumps::new(true, options)?)),
        other => Ok(Box::new(BlockElimination::new(make(other, false, options)?))),
    }
}

#[cfg(test)]
mod tests {
    //! The Schur complement, condensation and expansion of every backend against the dense
    //! definition S = A_KK − A_KI A_II⁻¹ A_IK computed here by Gauss elimination.
    use super::*;

    /// A symmetric positive definite banded matrix (a chain of springs to ground), with the kept
    /// unknowns spread through it.
    fn chain(n: usize) -> (CscMatrix, Vec<usize>) {
        let mut t = Triplets::default();
        for i in 0..n {
            t.push(i, i, 4.0 + (i % 3) as f64);
            if i + 1 < n {
                t.push(i, i + 1, -1.0 - 0.1 * (i % 2) as f64);
                t.push(i + 1, i, -1.0 - 0.1 * (i % 2) as f64);
            }
            if i + 5 < n {
                t.push(i, i + 5, -0.5);
                t.push(i + 5, i, -0.5);
            }
        }
        let (m, _) = PatternCache::default().assemble(n, &t);
        (m, vec![2, 7, 8, 15, n - 1])
    }

    fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for c in 0..n {
            let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
            a.swap(c, p);
            b.swap(c, p);
            for r in c + 1..n {
                let f = a[r][c] / a[c][c];
                for k in c..n {
                    a[r][k] -= f * a[c][k];
                }
                b[r] -= f * b[c];
            }
        }
        let mut x = vec![0.0; n];
        for r in (0..n).rev() {
            x[r] = (b[r] - (r + 1..n).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
        }
        x
    }

    fn check(mut condensing: Box<dyn Condensing>) {
        let n = 24;
        let (a, kept) = chain(n);
        let dense = a.to_dense();
        let interior: Vec<usize> = (0..n).filter(|e| !kept.contains(e)).collect();
        let sub = |rows: &[usize], cols: &[usize]| -> Vec<Vec<f64>> {
            rows.iter().map(|&i| cols.iter().map(|&j| dense[i][j]).collect()).collect()
        };
        let a_ii = sub(&interior, &interior);
        let m = kept.len();
        let schur = condensing.factorize_condensed(&a, &kept).expect("factorised");
        for b in 0..m {
            let col: Vec<f64> = interior.iter().map(|&i| dense[i][kept[b]]).collect();
            let w = dense_solve(a_ii.clone(), col);
            for a_ in 0..m {
                let expected = dense[kept[a_]][kept[b]]
                    - interior.iter().zip(&w).map(|(&i, wi)| dense[kept[a_]][i] * wi).sum::<f64>();
                let got = schur[a_ * m + b];
                assert!(
                    (got - expected).abs() < 1e-12 * expected.abs().max(1.0),
                    "{}: S[{a_}][{b}] = {got}, expected {expected}",
                    condensing.backend().name()
                );
            }
        }
        // a whole solve through condensation, the small dense solve and expansion
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let reduced = condensing.condense(&rhs).expect("condensed");
        let s_rows: Vec<Vec<f64>> = (0..m).map(|i| schur[i * m..(i + 1) * m].to_vec()).collect();
        let x_kept = dense_solve(s_rows, reduced);
        let x = condensing.expand(&rhs, &x_kept).expect("expanded");
        let ax = a.mul_vec(&x);
        for (i, (l, r)) in ax.iter().zip(&rhs).enumerate() {
            assert!((l - r).abs() < 1e-12, "{}: equation {i}: {l} against {r}", condensing.backend().name());
        }
    }

    #[test]
    fn every_backend_condenses_to_the_dense_schur_complement() {
        for backend in Backend::available() {
            check(make_condensing(backend, &SolverOptions::default()).expect("backend starts"));
        }
    }

    #[test]
    fn block_elimination_with_no_interior_keeps_the_matrix() {
        let (a, _) = chain(6);
        let kept: Vec<usize> = (0..6).collect();
        let mut b = BlockElimination::new(make(Backend::Faer, false, &SolverOptions::default()).unwrap());
        let s = b.factorize_condensed(&a, &kept).unwrap();
        let dense = a.to_dense();
        for i in 0..6 {
            for j in 0..6 {
                assert_eq!(s[i * 6 + j], dense[i][j]);
            }
        }
    }
}
