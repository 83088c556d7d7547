//! The kept unknowns that the interior of L reaches, apart from those it does not.
//!
//! The soil's Schur complement S = L_KK − L_KI L_II⁻¹ L_IK differs from L_KK only in the rows and
//! columns of the kept unknowns that L couples to the interior (K₁: the soil's interface unknowns, a
//! bar node next to a free length). The others (K₂: the bars' unknowns along the interface, the
//! multipliers) have S = L there exactly, a few entries or none. So only K₁ is handed to the
//! backend's condensation, on L with K₂'s rows and columns left out (their multipliers would make
//! its interior singular anyway), and S is made of the backend's dense S₁₁ and L's entries in K₂'s
//! rows and columns:
//!
//! ```text
//! S = [ S₁₁    L_K₁K₂ ]     r̃_K₂ = r_K₂,   x_I = L_II⁻¹ (r_I − L_IK₁ x_K₁)
//!     [ L_K₂K₁ L_K₂K₂ ]
//! ```
//!
//! At the pull-out box of 10⁵ unknowns the backend's Schur complement is of 1012 unknowns instead
//! of 2280 (MUMPS's last front and its dense copy a fifth of the size).

use super::csc::CscMatrix;
use super::kept_matrix::FixedPart;
use super::schur::Condensing;
use super::Failure;

const NONE: usize = usize::MAX;

/// How L was reduced before its condensation.
pub struct CoupledKept {
    /// Equation → its number in the reduced L (the equations of K₂ left out), or NONE.
    reduced_of: Vec<usize>,
    reduced_n: usize,
    /// Positions among the kept unknowns of K₁ and K₂.
    coupled: Vec<usize>,
    apart: Vec<usize>,
    /// The kept equations (as in the condensation's `kept`).
    kept: Vec<usize>,
}

impl CoupledKept {
    /// Condense `matrix` onto `kept` (sorted equations) with `condensing`: S as a [`FixedPart`],
    /// and the reduction the right-hand sides and solutions go through.
    ///
    /// # Errors
    /// The backend's failure.
    pub fn condense_onto(
        condensing: &mut dyn Condensing,
        matrix: &CscMatrix,
        kept: &[usize],
    ) -> Result<(FixedPart, CoupledKept), Failure> {
        let n = matrix.pattern.n();
        let mut position = vec![NONE; n];
        for (k, &e) in kept.iter().enumerate() {
            position[e] = k;
        }
        // which kept unknowns L couples to the interior
        let (col_ptr, row_idx) = (matrix.pattern.col_ptr(), matrix.pattern.row_idx());
        let mut reached = vec![false; kept.len()];
        for j in 0..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                match (position[i], position[j]) {
                    (NONE, NONE) => {}
                    (p, NONE) | (NONE, p) => reached[p] = true,
                    _ => {}
                }
            }
        }
        let coupled: Vec<usize> = (0..kept.len()).filter(|&k| reached[k]).collect();
        let apart: Vec<usize> = (0..kept.len()).filter(|&k| !reached[k]).collect();
        if coupled.is_empty() || apart.is_empty() {
            // nothing to leave out (or nothing the interior reaches): L condensed as it is
            let s = condensing.factorize_condensed(matrix, kept)?;
            let fixed = FixedPart::from_row_major(kept.len(), &s);
            let whole = CoupledKept {
                reduced_of: (0..n).collect(),
                reduced_n: n,
                coupled: (0..kept.len()).collect(),
                apart: Vec::new(),
                kept: kept.to_vec(),
            };
            return Ok((fixed, whole));
        }
        let mut reduced_of = vec![NONE; n];
        let mut reduced_n = 0;
        for (e, r) in reduced_of.iter_mut().enumerate() {
            if position[e] == NONE || reached[position[e]] {
                *r = reduced_n;
                reduced_n += 1;
            }
        }
        // the reduced L, and L's entries in K₂'s rows or columns (both kept: K₂ has no interior
        // entries)
        let new_index: Vec<Option<usize>> = reduced_of.iter().map(|&r| (r != NONE).then_some(r)).collect();
        let (reduced_matrix, left_out) = matrix.principal_submatrix(&new_index, reduced_n);
        drop(new_index);
        let entries: Vec<(usize, usize, f64)> =
            left_out.into_iter().map(|(i, j, v)| (position[i], position[j], v)).collect();
        let reduced_kept: Vec<usize> = coupled.iter().map(|&k| reduced_of[kept[k]]).collect();
        let s11 = condensing.factorize_condensed(&reduced_matrix, &reduced_kept)?;
        drop(reduced_matrix);
        let fixed = FixedPart::from_blocks(kept.len(), &coupled, &s11, entries);
        Ok((fixed, CoupledKept { reduced_of, reduced_n, coupled, apart, kept: kept.to_vec() }))
    }

    /// The kept equations, sorted.
    pub fn kept(&self) -> &[usize] {
        &self.kept
    }

    /// The kept unknowns the interior reaches (K₁) and the others (K₂).
    pub fn counts(&self) -> (usize, usize) {
        (self.coupled.len(), self.apart.len())
    }

    fn reduce(&self, rhs: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.reduced_n];
        for (e, &r) in self.reduced_of.iter().enumerate() {
            if r != NONE {
                out[r] = rhs[e];
            }
        }
        out
    }

    /// r_K − L_KI L_II⁻¹ r_I, in the order of the kept unknowns.
    ///
    /// # Errors
    /// The backend's failure.
    pub fn condense(&self, condensing: &mut dyn Condensing, rhs: &[f64]) -> Result<Vec<f64>, Failure> {
        let r1 = condensing.condense(&self.reduce(rhs))?;
        let mut out = vec![0.0; self.kept.len()];
        for (a, &k) in self.coupled.iter().enumerate() {
            out[k] = r1[a];
        }
        for &k in &self.apart {
            out[k] = rhs[self.kept[k]];
        }
        Ok(out)
    }

    /// The solution on every unknown from the one on the kept unknowns.
    ///
    /// # Errors
    /// The backend's failure.
    pub fn expand(
        &self,
        condensing: &mut dyn Condensing,
        rhs: &[f64],
        kept_solution: &[f64],
    ) -> Result<Vec<f64>, Failure> {
        let x1: Vec<f64> = self.coupled.iter().map(|&k| kept_solution[k]).collect();
        let reduced = condensing.expand(&self.reduce(rhs), &x1)?;
        let mut x = vec![0.0; self.reduced_of.len()];
        for (e, &r) in self.reduced_of.iter().enumerate() {
            if r != NONE {
                x[e] = reduced[r];
            }
        }
        for &k in &self.apart {
            x[self.kept[k]] = kept_solution[k];
        }
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    //! The condensation through K₁ alone against the dense definition S = L_KK − L_KI L_II⁻¹ L_IK on
    //! every backend: a chain of springs (the soil), a bar of two unknowns tied to one kept soil
    //! unknown and not to the interior, and a multiplier with nothing in L.
    use super::*;
    use crate::linsol::csc::{PatternCache, Triplets};
    use crate::linsol::{make_condensing, Backend, SolverOptions};
    use faer::linalg::solvers::Solve;
    use faer::Mat;

    fn model() -> (CscMatrix, Vec<usize>) {
        let n = 27;
        let mut t = Triplets::default();
        for i in 0..24 {
            t.push(i, i, 4.0 + (i % 3) as f64);
            if i + 1 < 24 {
                t.push(i, i + 1, -1.0 - 0.1 * (i % 2) as f64);
                t.push(i + 1, i, -1.0 - 0.1 * (i % 2) as f64);
            }
        }
        // the bar: 24 and 25, 24 tied to the kept soil unknown 7
        for (i, j, v) in [(24, 24, 3.0), (25, 25, 2.0), (24, 25, -2.0), (25, 24, -2.0), (24, 7, -1.0), (7, 24, -1.0)] {
            t.push(i, j, v);
        }
        t.push(7, 7, 1.0);
        // the multiplier: an explicit zero diagonal
        t.push(26, 26, 0.0);
        let (m, _) = PatternCache::default().assemble(n, &t);
        (m, vec![2, 7, 8, 15, 23, 24, 25, 26])
    }

    #[test]
    fn condensing_the_coupled_kept_unknowns_alone_gives_the_whole_schur_complement() {
        let (a, kept) = model();
        let n = a.pattern.n();
        let m = kept.len();
        let dense = a.to_dense();
        let interior: Vec<usize> = (0..n).filter(|e| !kept.contains(e)).collect();
        // the definition, by Gauss elimination of the interior (faer's dense LU)
        let a_ii = Mat::from_fn(interior.len(), interior.len(), |p, q| dense[interior[p]][interior[q]]);
        let a_ik = Mat::from_fn(interior.len(), m, |p, q| dense[interior[p]][kept[q]]);
        let w = a_ii.partial_piv_lu().solve(&a_ik);
        let expected = Mat::from_fn(m, m, |p, q| {
            dense[kept[p]][kept[q]] - (0..interior.len()).map(|r| dense[kept[p]][interior[r]] * w[(r, q)]).sum::<f64>()
        });
        for backend in Backend::available() {
            let mut condensing = make_condensing(backend, &SolverOptions::default()).expect("backend starts");
            let (fixed, coupled) = CoupledKept::condense_onto(condensing.as_mut(), &a, &kept).expect("condensed");
            assert_eq!(coupled.counts(), (5, 3), "{}: the bar and the multiplier are left out", backend.name());
            let s = fixed.times(Mat::<f64>::identity(m, m).as_ref());
            for p in 0..m {
                for q in 0..m {
                    let (got, want) = (s[(p, q)], expected[(p, q)]);
                    assert!(
                        (got - want).abs() < 1e-12 * want.abs().max(1.0),
                        "{}: S[{p}][{q}] = {got}, not {want}",
                        backend.name()
                    );
                }
            }
            // a whole solve of (L + C) x = b, C a unit diagonal on the multiplier: condensed,
            // solved densely on the kept unknowns, expanded
            let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            let reduced = coupled.condense(condensing.as_mut(), &rhs).expect("condensed");
            let mut kept_matrix = expected.clone();
            kept_matrix[(m - 1, m - 1)] += 1.0;
            let x_kept = kept_matrix.partial_piv_lu().solve(&Mat::from_fn(m, 1, |p, _| reduced[p]));
            let x_kept: Vec<f64> = (0..m).map(|p| x_kept[(p, 0)]).collect();
            let x = coupled.expand(condensing.as_mut(), &rhs, &x_kept).expect("expanded");
            let mut ax = a.mul_vec(&x);
            ax[26] += x[26];
            for (i, (l, r)) in ax.iter().zip(&rhs).enumerate() {
                assert!((l - r).abs() < 1e-12, "{}: equation {i}: {l} against {r}", backend.name());
            }
        }
    }
}
