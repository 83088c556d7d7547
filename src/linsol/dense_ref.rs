//! Dense Gauss elimination with complete pivoting: the reference backend.
//!
//! The paper's Eq. (7) is misprinted (its multiplier is K_kk/K_kk); this is the standard form,
//! K_ij ← K_ij − (K_ik / K_kk)·K_kj, with row and column interchanges choosing the largest remaining
//! entry as the pivot (Golub & Van Loan, Matrix Computations, §3.4.2). A zero pivot means the
//! remaining unknowns are not determined: they are reported as singular.

use super::{Backend, Failure, LinearSolver};
use crate::error::SolveError;
use crate::linsol::csc::CscMatrix;

/// Largest system the reference solver accepts (O(n³) work, n² memory).
pub const SIZE_LIMIT: usize = 3000;

#[derive(Debug, Default)]
pub struct DenseReference {
    n: usize,
    /// L (unit, below the diagonal) and U (on and above) of P A Q, row-major.
    lu: Vec<f64>,
    /// row_perm[k]: original row in position k; col_perm[k]: original column (unknown) in position k.
    row_perm: Vec<usize>,
    col_perm: Vec<usize>,
}

impl LinearSolver for DenseReference {
    fn backend(&self) -> Backend {
        Backend::Dense
    }

    fn analyse(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        let pattern = &matrix.pattern;
        if pattern.n() > SIZE_LIMIT {
            return Err(SolveError::TooLarge { size: pattern.n(), limit: SIZE_LIMIT }.into());
        }
        self.n = pattern.n();
        Ok(())
    }

    fn factorize(&mut self, matrix: &CscMatrix) -> Result<(), Failure> {
        let n = self.n;
        let mut a = vec![0.0; n * n];
        let p = &matrix.pattern;
        for j in 0..n {
            for k in p.col_ptr()[j]..p.col_ptr()[j + 1] {
                a[p.row_idx()[k] * n + j] += matrix.values[k];
            }
        }
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let tiny = scale * f64::EPSILON * (n.max(1) as f64) * 16.0;
        let mut rp: Vec<usize> = (0..n).collect();
        let mut cp: Vec<usize> = (0..n).collect();
        for k in 0..n {
            // complete pivoting: largest |a_ij| in the remaining block
            let (mut pi, mut pj, mut best) = (k, k, -1.0);
            for i in k..n {
                for j in k..n {
                    let v = a[i * n + j].abs();
                    if v > best {
                        best = v;
                        pi = i;
                        pj = j;
                    }
                }
            }
            if !(best > tiny) {
                return Err(Failure::Singular { equations: cp[k..].to_vec() });
            }
            if pi != k {
                for j in 0..n {
                    a.swap(k * n + j, pi * n + j);
                }
                rp.swap(k, pi);
            }
            if pj != k {
                for i in 0..n {
                    a.swap(i * n + k, i * n + pj);
                }
                cp.swap(k, pj);
            }
            let pivot = a[k * n + k];
            for i in k + 1..n {
                let m = a[i * n + k] / pivot; // the multiplier K_ik / K_kk
                if m != 0.0 {
                    a[i * n + k] = m;
                    for j in k + 1..n {
                        a[i * n + j] -= m * a[k * n + j];
                    }
                } else {
                    a[i * n + k] = 0.0;
                }
            }
        }
        self.lu = a;
        self.row_perm = rp;
        self.col_perm = cp;
        Ok(())
    }

    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        let n = self.n;
        let a = &self.lu;
        // forward: L y = P b
        let mut y: Vec<f64> = self.row_perm.iter().map(|&r| rhs[r]).collect();
        for i in 0..n {
            let mut s = y[i];
            for j in 0..i {
                s -= a[i * n + j] * y[j];
            }
            y[i] = s;
        }
        // backward: U z = y
        for i in (0..n).rev() {
            let mut s = y[i];
            for j in i + 1..n {
                s -= a[i * n + j] * y[j];
            }
            y[i] = s / a[i * n + i];
        }
        // x = Q z
        let mut x = vec![0.0; n];
        for (k, &c) in self.col_perm.iter().enumerate() {
            x[c] = y[k];
        }
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linsol::csc::{PatternCache, Triplets};

    fn matrix(rows: &[&[f64]]) -> CscMatrix {
        let mut t = Triplets::default();
        for (i, r) in rows.iter().enumerate() {
            for (j, v) in r.iter().enumerate() {
                if *v != 0.0 || i == j {
                    t.push(i, j, *v);
                }
            }
        }
        PatternCache::default().assemble(rows.len(), &t).0
    }

    #[test]
    fn saddle_point_with_zero_diagonal_is_solved() {
        // K = [[2, -1], [-1, 2]], one multiplier tying u0 = u1: exact solution by hand.
        // [2 -1 1; -1 2 -1; 1 -1 0] x = [1, 0, 0]: u0 = u1 = u, u + λ = 1 and u − λ = 0,
        // so u0 = u1 = λ = 1/2.
        let a = matrix(&[&[2.0, -1.0, 1.0], &[-1.0, 2.0, -1.0], &[1.0, -1.0, 0.0]]);
        let mut s = DenseReference::default();
        s.analyse(&a).unwrap();
        s.factorize(&a).unwrap();
        let x = s.solve(&[1.0, 0.0, 0.0]).unwrap();
        for (v, e) in x.iter().zip([0.5, 0.5, 0.5]) {
            assert!((v - e).abs() < 1e-14, "{x:?}");
        }
    }

    #[test]
    fn singular_matrix_names_the_free_unknown() {
        // unknown 1 has no stiffness and no constraint
        let a = matrix(&[&[2.0, 0.0, 0.0], &[0.0, 0.0, 0.0], &[0.0, 0.0, 3.0]]);
        let mut s = DenseReference::default();
        s.analyse(&a).unwrap();
        match s.factorize(&a) {
            Err(Failure::Singular { equations }) => assert_eq!(equations, vec![1]),
            other => panic!("expected singular, got {other:?}"),
        }
    }
}
