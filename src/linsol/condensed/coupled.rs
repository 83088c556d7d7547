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
//!
//! A new L often differs from the last only in K₂ and in how the equations are numbered: a stage
//! that prescribes a reinforcement's head takes the head's unknown out of the equations, but the
//! soil and the unknowns its interior reaches stay as they were. The reduced L is then the same
//! matrix, and its factorisation and S₁₁ are the last condensation's: they are kept, known by the
//! reduced L's fingerprint (its pattern, values and K₁), and the backend is not called. (A
//! fingerprint that matched a different matrix would be caught by the first solve's residual,
//! which is checked against the whole L + C: see `ready.rs`.)

use super::condensing::Condensing;
use super::kept::KeptUnknowns;
use super::kept_matrix::SoilSchur;
use crate::linsol::csc::CscMatrix;
use crate::linsol::Failure;
use std::rc::Rc;

const NONE: usize = usize::MAX;

/// How L was reduced before its condensation.
pub struct CoupledKept {
    /// Equation → its number in the reduced L (the equations of K₂ left out), or NONE.
    reduced_of: Vec<usize>,
    reduced_n: usize,
    /// Positions among the kept unknowns of K₁ and K₂.
    coupled: Vec<usize>,
    apart: Vec<usize>,
    /// The kept unknowns (as in the condensation's `kept`).
    kept: Rc<KeptUnknowns>,
    /// The fingerprint of the reduced L and K₁ in it, as handed to the backend.
    fingerprint: u64,
}

/// The reduced L's pattern, values and Schur unknowns, hashed.
fn fingerprint(matrix: &CscMatrix, schur_unknowns: &[usize]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    matrix.pattern.n().hash(&mut h);
    matrix.pattern.col_ptr().hash(&mut h);
    matrix.pattern.row_idx().hash(&mut h);
    matrix.values.iter().for_each(|v| v.to_bits().hash(&mut h));
    schur_unknowns.hash(&mut h);
    h.finish()
}

/// S₁₁ of the reduced L `matrix` on `schur_unknowns`: the last condensation's when its reduced L
/// was the same, or the backend's factorisation. Says which.
fn schur_block(
    condensing: &mut dyn Condensing,
    matrix: &CscMatrix,
    schur_unknowns: &[usize],
    last: Option<(SoilSchur, CoupledKept)>,
) -> Result<(Vec<f64>, u64, bool), Failure> {
    let key = fingerprint(matrix, schur_unknowns);
    if let Some((schur, coupled)) = last.filter(|(_, c)| c.fingerprint == key) {
        return Ok((schur.principal(&coupled.coupled), key, true));
    }
    Ok((condensing.factorize_condensed(matrix, schur_unknowns)?, key, false))
}

impl CoupledKept {
    /// Condense `matrix` onto `kept` (sorted equations) with `condensing`: S as a [`SoilSchur`],
    /// the reduction the right-hand sides and solutions go through, and whether the backend's
    /// factorisation was the one `last` (the last condensation with this backend, if any) was
    /// made with, its reduced L being the same.
    ///
    /// # Errors
    /// The backend's failure.
    pub fn condense_onto(
        condensing: &mut dyn Condensing,
        matrix: &CscMatrix,
        kept: &Rc<KeptUnknowns>,
        last: Option<(SoilSchur, CoupledKept)>,
    ) -> Result<(SoilSchur, CoupledKept, bool), Failure> {
        let n = matrix.pattern.n();
        let position = |e: usize| kept.position(e);
        // which kept unknowns L couples to the interior
        let (col_ptr, row_idx) = (matrix.pattern.col_ptr(), matrix.pattern.row_idx());
        let mut reached = vec![false; kept.len()];
        for j in 0..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                match (position(i), position(j)) {
                    (Some(p), None) | (None, Some(p)) => reached[p] = true,
                    _ => {}
                }
            }
        }
        let coupled: Vec<usize> = (0..kept.len()).filter(|&k| reached[k]).collect();
        let apart: Vec<usize> = (0..kept.len()).filter(|&k| !reached[k]).collect();
        if coupled.is_empty() || apart.is_empty() {
            // nothing to leave out (or nothing the interior reaches): L condensed as it is
            let (s, fingerprint, reused) = schur_block(condensing, matrix, kept.equations(), last)?;
            let schur = SoilSchur::from_row_major(kept.len(), &s);
            let whole = CoupledKept {
                reduced_of: (0..n).collect(),
                reduced_n: n,
                coupled: (0..kept.len()).collect(),
                apart: Vec::new(),
                kept: kept.clone(),
                fingerprint,
            };
            return Ok((schur, whole, reused));
        }
        let mut reduced_of = vec![NONE; n];
        let mut reduced_n = 0;
        for (e, r) in reduced_of.iter_mut().enumerate() {
            if position(e).is_none_or(|p| reached[p]) {
                *r = reduced_n;
                reduced_n += 1;
            }
        }
        // the reduced L, and L's entries in K₂'s rows or columns (both kept: K₂ has no interior
        // entries)
        let new_index: Vec<Option<usize>> = reduced_of.iter().map(|&r| (r != NONE).then_some(r)).collect();
        let (reduced_matrix, left_out) = matrix.principal_submatrix(&new_index, reduced_n);
        drop(new_index);
        let in_kept = |e: usize| kept.position(e).unwrap_or(usize::MAX);
        let entries: Vec<(usize, usize, f64)> =
            left_out.into_iter().map(|(i, j, v)| (in_kept(i), in_kept(j), v)).collect();
        let reduced_kept: Vec<usize> = coupled.iter().map(|&k| reduced_of[kept.equations()[k]]).collect();
        let (s11, fingerprint, reused) = schur_block(condensing, &reduced_matrix, &reduced_kept, last)?;
        drop(reduced_matrix);
        let schur = SoilSchur::from_blocks(kept.len(), &coupled, &s11, entries);
        Ok((schur, CoupledKept { reduced_of, reduced_n, coupled, apart, kept: kept.clone(), fingerprint }, reused))
    }

    /// The kept unknowns the interior reaches (K₁) and the others (K₂).
    #[cfg(test)]
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
            out[k] = rhs[self.kept.equations()[k]];
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
            x[self.kept.equations()[k]] = kept_solution[k];
        }
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    //! The condensation through K₁ alone against the dense definition S = L_KK − L_KI L_II⁻¹ L_IK on
    //! every backend: a chain of springs (the soil), a bar of two unknowns tied to one kept soil
    //! unknown and not to the interior, and a multiplier with nothing in L.
    use super::super::elimination::make_condensing;
    use super::*;
    use crate::linsol::csc::{PatternCache, Triplets};
    use crate::linsol::{Backend, SolverOptions};
    use faer::linalg::solvers::Solve;
    use faer::Mat;

    fn model() -> (CscMatrix, Vec<usize>) {
        model_with(true, 4.0)
    }

    /// The model, with the bar's far unknown (25) or without it (the multiplier is then 25), and
    /// the soil's diagonal starting at `diagonal`.
    fn model_with(far_end: bool, diagonal: f64) -> (CscMatrix, Vec<usize>) {
        let n = if far_end { 27 } else { 26 };
        let mut t = Triplets::default();
        for i in 0..24 {
            t.push(i, i, diagonal + (i % 3) as f64);
            if i + 1 < 24 {
                t.push(i, i + 1, -1.0 - 0.1 * (i % 2) as f64);
                t.push(i + 1, i, -1.0 - 0.1 * (i % 2) as f64);
            }
        }
        // the bar: 24 and 25, 24 tied to the kept soil unknown 7
        for (i, j, v) in [(24, 24, 3.0), (25, 25, 2.0), (24, 25, -2.0), (25, 24, -2.0), (24, 7, -1.0), (7, 24, -1.0)] {
            if far_end || (i != 25 && j != 25) {
                t.push(i, j, v);
            }
        }
        t.push(7, 7, 1.0);
        // the multiplier: an explicit zero diagonal
        t.push(n - 1, n - 1, 0.0);
        let (m, _) = PatternCache::default().assemble(n, &t);
        let kept = if far_end { vec![2, 7, 8, 15, 23, 24, 25, 26] } else { vec![2, 7, 8, 15, 23, 24, 25] };
        (m, kept)
    }

    /// S = L_KK − L_KI L_II⁻¹ L_IK by Gauss elimination of the interior (faer's dense LU).
    /// `kept` as the kept unknowns of `a`.
    fn of(a: &CscMatrix, kept: &[usize]) -> Rc<KeptUnknowns> {
        Rc::new(KeptUnknowns::new(a.pattern.n(), kept.to_vec()))
    }

    fn definition(a: &CscMatrix, kept: &[usize]) -> Mat<f64> {
        let n = a.pattern.n();
        let m = kept.len();
        let dense = a.to_dense();
        let interior: Vec<usize> = (0..n).filter(|e| !kept.contains(e)).collect();
        let a_ii = Mat::from_fn(interior.len(), interior.len(), |p, q| dense[interior[p]][interior[q]]);
        let a_ik = Mat::from_fn(interior.len(), m, |p, q| dense[interior[p]][kept[q]]);
        let w = a_ii.partial_piv_lu().solve(&a_ik);
        Mat::from_fn(m, m, |p, q| {
            dense[kept[p]][kept[q]] - (0..interior.len()).map(|r| dense[kept[p]][interior[r]] * w[(r, q)]).sum::<f64>()
        })
    }

    fn assert_equal(s: &SoilSchur, expected: &Mat<f64>, what: &str) {
        let m = expected.nrows();
        let s = s.times(Mat::<f64>::identity(m, m).as_ref());
        for p in 0..m {
            for q in 0..m {
                let (got, want) = (s[(p, q)], expected[(p, q)]);
                assert!((got - want).abs() < 1e-12 * want.abs().max(1.0), "{what}: S[{p}][{q}] = {got}, not {want}");
            }
        }
    }

    #[test]
    fn a_new_l_with_the_same_reduced_l_reuses_the_factorisation() {
        let (a, kept) = model();
        // the bar's far unknown taken out of the equations (the multiplier renumbered): the soil
        // and K₁ as they were
        let (shorter, shorter_kept) = model_with(false, 4.0);
        // a stiffer soil
        let (stiffer, _) = model_with(false, 4.5);
        for backend in Backend::available() {
            let mut condensing = make_condensing(backend, &SolverOptions::default()).expect("backend starts");
            let first = CoupledKept::condense_onto(condensing.as_mut(), &a, &of(&a, &kept), None).expect("condensed");
            let (schur, coupled, reused) = CoupledKept::condense_onto(
                condensing.as_mut(),
                &shorter,
                &of(&shorter, &shorter_kept),
                Some((first.0, first.1)),
            )
            .expect("condensed");
            assert!(reused, "{}: the same reduced L", backend.name());
            assert_equal(&schur, &definition(&shorter, &shorter_kept), backend.name());
            // and a whole solve through the reused factorisation
            let expected = definition(&shorter, &shorter_kept);
            assert_whole_solve(condensing.as_mut(), &coupled, &shorter, &expected, backend.name());
            let (schur, _, reused) = CoupledKept::condense_onto(
                condensing.as_mut(),
                &stiffer,
                &of(&stiffer, &shorter_kept),
                Some((schur, coupled)),
            )
            .expect("condensed");
            assert!(!reused, "{}: a different soil is factorised", backend.name());
            assert_equal(&schur, &definition(&stiffer, &shorter_kept), backend.name());
        }
    }

    #[test]
    fn condensing_the_coupled_kept_unknowns_alone_gives_the_whole_schur_complement() {
        let (a, kept) = model();
        let expected = definition(&a, &kept);
        for backend in Backend::available() {
            let mut condensing = make_condensing(backend, &SolverOptions::default()).expect("backend starts");
            let (schur, coupled, reused) =
                CoupledKept::condense_onto(condensing.as_mut(), &a, &of(&a, &kept), None).expect("condensed");
            assert!(!reused);
            assert_eq!(coupled.counts(), (5, 3), "{}: the bar and the multiplier are left out", backend.name());
            assert_equal(&schur, &expected, backend.name());
            assert_whole_solve(condensing.as_mut(), &coupled, &a, &expected, backend.name());
        }
    }

    /// A whole solve of (L + C) x = b, C a unit diagonal on the multiplier (the last unknown):
    /// condensed, solved densely on the kept unknowns with S = `schur`, expanded; x meets the
    /// equations.
    fn assert_whole_solve(
        condensing: &mut dyn Condensing,
        coupled: &CoupledKept,
        a: &CscMatrix,
        schur: &Mat<f64>,
        what: &str,
    ) {
        let (n, m) = (a.pattern.n(), schur.nrows());
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let reduced = coupled.condense(condensing, &rhs).expect("condensed");
        let mut kept_matrix = schur.clone();
        kept_matrix[(m - 1, m - 1)] += 1.0;
        let x_kept = kept_matrix.partial_piv_lu().solve(&Mat::from_fn(m, 1, |p, _| reduced[p]));
        let x_kept: Vec<f64> = (0..m).map(|p| x_kept[(p, 0)]).collect();
        let x = coupled.expand(condensing, &rhs, &x_kept).expect("expanded");
        let mut ax = a.mul_vec(&x);
        ax[n - 1] += x[n - 1];
        for (i, (l, r)) in ax.iter().zip(&rhs).enumerate() {
            assert!((l - r).abs() < 1e-12, "{what}: equation {i}: {l} against {r}");
        }
    }
}
