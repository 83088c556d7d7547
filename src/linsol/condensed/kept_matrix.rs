//! The interface's kept system as the soil's Schur complement and a changing sparse part, M = S + C.
//!
//! S is the soil's Schur complement on the kept unknowns (fixed while the soil is), C the
//! interface's springs and rows (a few entries a point, new in every iteration under large slip).
//! C is held by columns, so that which columns changed is found on C alone, and products with M
//! are S·x + C·x: no m × m array of M itself is ever formed. S is held as its dense block on the
//! unknowns where it is dense (the soil's) and its few entries elsewhere (the bars' stiffness): of
//! the pull-out box's 2280 kept unknowns at 10⁵, S is dense on 1016, a fifth of the m × m array.

use crate::linsol::csc::bucket_by_column;
use faer::dyn_stack::MemStack;
use faer::reborrow::ReborrowMut;
use faer::{Mat, MatMut, MatRef};

/// The entries a row and a column of S may hold and still be held apart from S's dense block (a
/// bar node's own stiffness: its two unknowns and its neighbours').
pub const SPARSE_ROW: usize = 16;

const NONE: usize = usize::MAX;

/// The soil's Schur complement S in a matrix S + C: a dense block on the unknowns whose row or column of S holds
/// more than [`SPARSE_ROW`] entries, and S's nonzero entries outside it.
#[derive(Debug, Clone)]
pub struct SoilSchur {
    order: usize,
    /// The unknowns of the dense block, increasing.
    dense: Vec<usize>,
    /// Each unknown's position among `dense`, or NONE.
    position: Vec<usize>,
    /// S on `dense` × `dense`.
    block: Mat<f64>,
    /// S's nonzero entries (i, j, value) with i or j outside `dense`.
    entries: Vec<(usize, usize, f64)>,
    /// Whether S has anything in row or column j.
    in_fixed: Vec<bool>,
}

impl SoilSchur {
    /// S of order `order` from its entries by rows.
    pub fn from_row_major(order: usize, values: &[f64]) -> SoilSchur {
        let all: Vec<usize> = (0..order).collect();
        SoilSchur::from_blocks(order, &all, values, Vec::new())
    }

    /// S on the rows and columns `positions` (of its unknowns), by rows: the `coupled_block` it
    /// was made from ([`SoilSchur::from_blocks`]) when `positions` are those `coupled`.
    pub fn principal(&self, positions: &[usize]) -> Vec<f64> {
        let k = positions.len();
        let mut at = vec![NONE; self.order];
        for (a, &p) in positions.iter().enumerate() {
            at[p] = a;
        }
        let mut out = vec![0.0; k * k];
        for (a, &i) in self.dense.iter().enumerate() {
            if at[i] == NONE {
                continue;
            }
            for (b, &j) in self.dense.iter().enumerate() {
                if at[j] != NONE {
                    out[at[i] * k + at[j]] = self.block[(a, b)];
                }
            }
        }
        for &(i, j, v) in &self.entries {
            if at[i] != NONE && at[j] != NONE {
                out[at[i] * k + at[j]] += v;
            }
        }
        out
    }

    /// S from a dense matrix.
    #[cfg(test)]
    pub fn from_dense(f: MatRef<'_, f64>) -> SoilSchur {
        assert_eq!(f.nrows(), f.ncols(), "S is square");
        let m = f.nrows();
        let values: Vec<f64> = (0..m * m).map(|k| f[(k / m, k % m)]).collect();
        SoilSchur::from_row_major(m, &values)
    }

    /// S of order `order` from its dense part `coupled_block` (row by row) on the unknowns
    /// `coupled` (increasing) and its entries elsewhere (`entries`: (i, j, value), each in a row or
    /// column outside `coupled`).
    pub fn from_blocks(
        order: usize,
        coupled: &[usize],
        coupled_block: &[f64],
        entries: Vec<(usize, usize, f64)>,
    ) -> SoilSchur {
        let k = coupled.len();
        assert_eq!(coupled_block.len(), k * k, "the coupled block is k × k");
        let (mut in_row, mut in_column) = (vec![0usize; order], vec![0usize; order]);
        for a in 0..k {
            for b in 0..k {
                if coupled_block[a * k + b] != 0.0 {
                    in_row[coupled[a]] += 1;
                    in_column[coupled[b]] += 1;
                }
            }
        }
        let entries: Vec<(usize, usize, f64)> = entries.into_iter().filter(|e| e.2 != 0.0).collect();
        for &(i, j, _) in &entries {
            in_row[i] += 1;
            in_column[j] += 1;
        }
        let dense: Vec<usize> = (0..order).filter(|&j| in_row[j] > SPARSE_ROW || in_column[j] > SPARSE_ROW).collect();
        let mut position = vec![NONE; order];
        for (p, &j) in dense.iter().enumerate() {
            position[j] = p;
        }
        let mut block = Mat::zeros(dense.len(), dense.len());
        let mut outside = Vec::new();
        let mut place = |i: usize, j: usize, v: f64| {
            if position[i] != NONE && position[j] != NONE {
                block[(position[i], position[j])] += v;
            } else {
                outside.push((i, j, v));
            }
        };
        for a in 0..k {
            for b in 0..k {
                let v = coupled_block[a * k + b];
                if v != 0.0 {
                    place(coupled[a], coupled[b], v);
                }
            }
        }
        for (i, j, v) in entries {
            place(i, j, v);
        }
        let in_fixed = (0..order).map(|j| in_row[j] > 0 || in_column[j] > 0).collect();
        SoilSchur { order, dense, position, block, entries: outside, in_fixed }
    }

    pub fn order(&self) -> usize {
        self.order
    }

    /// Whether S has anything in row or column j.
    pub fn in_schur(&self, j: usize) -> bool {
        self.in_fixed[j]
    }

    /// Whether unknown j lies outside S's dense block (its row and column of S are sparse).
    pub fn is_sparse(&self, j: usize) -> bool {
        self.position[j] == NONE
    }

    /// S's nonzero entries outside its dense block.
    pub fn sparse_entries(&self) -> &[(usize, usize, f64)] {
        &self.entries
    }

    /// S·x.
    pub fn times(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let columns = x.ncols();
        let mut out = Mat::zeros(self.order, columns);
        let x_dense = Mat::from_fn(self.dense.len(), columns, |p, c| x[(self.dense[p], c)]);
        let y = &self.block * &x_dense;
        for (p, &i) in self.dense.iter().enumerate() {
            for c in 0..columns {
                out[(i, c)] = y[(p, c)];
            }
        }
        for &(i, j, v) in &self.entries {
            for c in 0..columns {
                out[(i, c)] += v * x[(j, c)];
            }
        }
        out
    }

    /// S on the unknowns `among` (increasing) into `out` (of their number).
    fn write_into(&self, mut out: MatMut<'_, f64>, among: &[usize]) {
        out.fill(0.0);
        // the members of the dense block: (position in `among`, position in the block)
        let in_block: Vec<(usize, usize)> = among
            .iter()
            .enumerate()
            .filter(|(_, &j)| self.position[j] != NONE)
            .map(|(p, &j)| (p, self.position[j]))
            .collect();
        for &(q, bq) in &in_block {
            let block_column = self.block.col(bq);
            let mut out_column = out.rb_mut().col_mut(q);
            for &(p, bp) in &in_block {
                out_column[p] = block_column[bp];
            }
        }
        if self.entries.is_empty() {
            return;
        }
        let mut position = vec![NONE; self.order];
        for (p, &i) in among.iter().enumerate() {
            position[i] = p;
        }
        for &(i, j, v) in &self.entries {
            if position[i] != NONE && position[j] != NONE {
                out[(position[i], position[j])] += v;
            }
        }
    }
}

/// The sparse part C of a matrix S + C, by columns: entries of one position summed, rows in
/// increasing order within a column.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseColumns {
    col_ptr: Vec<usize>,
    rows: Vec<usize>,
    values: Vec<f64>,
}

impl SparseColumns {
    /// C of order `m` from its entries (row, column, value) in any order, repeated positions
    /// added (in the order they come). Bucketed by column, then each column's few entries sorted by
    /// row: no sort of the whole list (an interface's C is rebuilt every iteration).
    pub fn from_entries(m: usize, entries: impl Iterator<Item = (usize, usize, f64)>) -> SparseColumns {
        let list: Vec<(usize, usize, f64)> = entries.collect();
        let (mut bucketed, start) = bucket_by_column(m, list.len(), |k| list[k].1, |k| (list[k].0, list[k].2));
        drop(list);
        let mut col_ptr = vec![0; m + 1];
        let mut rows = Vec::with_capacity(bucketed.len());
        let mut values = Vec::with_capacity(bucketed.len());
        for j in 0..m {
            let column = &mut bucketed[start[j]..start[j + 1]];
            // stable: repeated positions are added in the order they came
            column.sort_by_key(|&(i, _)| i);
            let mut last = None;
            for &(i, v) in column.iter() {
                match values.last_mut() {
                    Some(sum) if last == Some(i) => *sum += v,
                    _ => {
                        rows.push(i);
                        values.push(v);
                        last = Some(i);
                    }
                }
            }
            col_ptr[j + 1] = rows.len();
        }
        SparseColumns { col_ptr, rows, values }
    }

    pub(super) fn order(&self) -> usize {
        self.col_ptr.len().saturating_sub(1)
    }

    /// Column j: its rows and values.
    pub(super) fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.rows[range.clone()], &self.values[range])
    }

    /// Whether column j holds the same entries, bit for bit, in `other`.
    pub(super) fn same_column(&self, other: &SparseColumns, j: usize) -> bool {
        let (a, b) = (self.column(j), other.column(j));
        a.0 == b.0 && a.1.iter().zip(b.1).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// C·x.
    pub fn times(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let mut out = Mat::zeros(self.order(), x.ncols());
        self.add_times(x, out.as_mut());
        out
    }

    /// out += C·x.
    pub(super) fn add_times(&self, x: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
        for j in 0..self.order() {
            let (rows, values) = self.column(j);
            for c in 0..x.ncols() {
                let xj = x[(j, c)];
                if xj != 0.0 {
                    for (&i, &v) in rows.iter().zip(values) {
                        out[(i, c)] += v * xj;
                    }
                }
            }
        }
    }
}

/// The matrix S + C as an operator: S·x + C·x.
#[derive(Debug, Clone, Copy)]
pub struct KeptMatrix<'a> {
    pub schur: &'a SoilSchur,
    pub change: &'a SparseColumns,
}

impl KeptMatrix<'_> {
    /// The order of the matrix.
    pub fn order(&self) -> usize {
        self.schur.order()
    }

    /// (S + C)·x.
    pub fn times(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let mut out = self.schur.times(x);
        self.change.add_times(x, out.as_mut());
        out
    }

    /// S + C on the unknowns `among` (increasing), as a dense matrix into `out` (of their number).
    pub(super) fn write_into(&self, mut out: MatMut<'_, f64>, among: &[usize]) {
        self.schur.write_into(out.rb_mut(), among);
        let mut position = vec![NONE; self.order()];
        for (p, &i) in among.iter().enumerate() {
            position[i] = p;
        }
        for &j in among {
            let (rows, values) = self.change.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                if position[i] != NONE {
                    out[(position[i], position[j])] += v;
                }
            }
        }
    }
}

impl faer::matrix_free::LinOp<f64> for KeptMatrix<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: faer::Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.order()
    }
    fn ncols(&self) -> usize {
        self.order()
    }
    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: faer::Par, _: &mut MemStack) {
        out.copy_from(self.times(rhs));
    }
    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: faer::Par, stack: &mut MemStack) {
        // real: the conjugate is the operator itself
        self.apply(out, rhs, par, stack)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_entries_are_summed_and_columns_compared_bit_for_bit() {
        let c = SparseColumns::from_entries(3, [(2, 1, 1.0), (0, 1, 2.0), (2, 1, 0.5)].into_iter());
        assert_eq!(c.column(1), (&[0usize, 2][..], &[2.0, 1.5][..]));
        assert_eq!(c.column(0).0.len() + c.column(2).0.len(), 0);
        let d = SparseColumns::from_entries(3, [(0, 1, 2.0), (2, 1, 1.5 + 1e-16)].into_iter());
        assert!(c.same_column(&d, 0) && c.same_column(&d, 2));
        assert_eq!(c.same_column(&d, 1), (1.5f64 + 1e-16).to_bits() == 1.5f64.to_bits());
        let e = SparseColumns::from_entries(3, [(0, 1, 2.0), (1, 1, 1.5)].into_iter());
        assert!(!c.same_column(&e, 1), "the same values in other rows");
    }
}
