//! Triplets → compressed sparse columns, with the pattern computed once and the values refilled
//! through a precomputed map (no re-sorting).

use std::sync::Arc;

/// A square sparsity pattern in compressed sparse column form. Row indices are sorted and unique
/// within each column; every index is below `n` (checked when built, so no later code re-checks).
#[derive(Debug, Clone, PartialEq)]
pub struct CscPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl CscPattern {
    pub fn n(&self) -> usize {
        self.n
    }
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Build the pattern of a triplet list and the map from each triplet to its stored entry.
    ///
    /// # Panics
    /// If a triplet index is not below `n` (the assembler only produces valid indices).
    pub fn from_triplets(n: usize, rows: &[u32], cols: &[u32]) -> (CscPattern, Vec<u32>) {
        assert_eq!(rows.len(), cols.len());
        assert!(rows.iter().chain(cols).all(|&i| (i as usize) < n), "triplet index out of range");
        // Order by column, then by row inside each column; equal keys share one entry. (A list's
        // length fits 32 bits: `Triplets::push` holds it there.) The triplets are bucketed by
        // column first (a counting sort) and each column's few sorted by row: a sort of the
        // whole list by its indirect key took most of a 10⁵-unknown soil's assembly.
        let key = |k: u32| (cols[k as usize], rows[k as usize]);
        let (mut order, start) = bucket_by_column(n, rows.len(), |k| cols[k] as usize, |k| k as u32);
        for j in 0..n {
            order[start[j]..start[j + 1]].sort_unstable_by_key(|&k| rows[k as usize]);
        }
        drop(start);
        let distinct = order.windows(2).filter(|w| key(w[0]) != key(w[1])).count() + usize::from(!order.is_empty());
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(distinct);
        let mut map = vec![0u32; rows.len()];
        let mut last = None;
        for &k in &order {
            let (col, row) = key(k);
            if last != Some((col, row)) {
                row_idx.push(row as usize);
                col_ptr[col as usize + 1] += 1;
                last = Some((col, row));
            }
            map[k as usize] = (row_idx.len() - 1) as u32;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        (CscPattern { n, col_ptr, row_idx }, map)
    }
}

/// A matrix: a shared pattern and its values.
#[derive(Debug, Clone)]
pub struct CscMatrix {
    pub pattern: Arc<CscPattern>,
    pub values: Vec<f64>,
}

impl CscMatrix {
    /// y = A x
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let p = &self.pattern;
        let mut y = vec![0.0; p.n];
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                y[p.row_idx[k]] += self.values[k] * x[j];
            }
        }
        y
    }

    /// The rows and columns `new_index` maps to a number (in the same order as the equations:
    /// increasing), as a matrix of `n_new` equations, and every entry left out, as (row, column,
    /// value) of this matrix. No sort: an increasing map keeps each column's rows sorted.
    ///
    /// # Panics
    /// If the numbers `new_index` gives are not increasing and below `n_new`.
    pub fn principal_submatrix(
        &self,
        new_index: &[Option<usize>],
        n_new: usize,
    ) -> (CscMatrix, Vec<(usize, usize, f64)>) {
        let p = &self.pattern;
        assert_eq!(new_index.len(), p.n);
        let numbers: Vec<usize> = new_index.iter().flatten().copied().collect();
        assert!(
            numbers.len() == n_new && numbers.iter().enumerate().all(|(k, &r)| k == r),
            "not an increasing map onto 0..n_new"
        );
        let mut col_ptr = Vec::with_capacity(n_new + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::with_capacity(p.row_idx.len());
        let mut values = Vec::with_capacity(p.row_idx.len());
        let mut left_out = Vec::new();
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                let i = p.row_idx[k];
                match (new_index[i], new_index[j]) {
                    (Some(r), Some(_)) => {
                        row_idx.push(r);
                        values.push(self.values[k]);
                    }
                    _ => left_out.push((i, j, self.values[k])),
                }
            }
            if new_index[j].is_some() {
                col_ptr.push(row_idx.len());
            }
        }
        row_idx.shrink_to_fit();
        values.shrink_to_fit();
        let pattern = CscPattern { n: n_new, col_ptr, row_idx };
        (CscMatrix { pattern: Arc::new(pattern), values }, left_out)
    }

    /// Dense copy (for the reference solver and small diagnostics).
    pub fn to_dense(&self) -> Vec<Vec<f64>> {
        let p = &self.pattern;
        let mut a = vec![vec![0.0; p.n]; p.n];
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                a[p.row_idx[k]][j] += self.values[k];
            }
        }
        a
    }

    /// Whether the matrix is numerically symmetric (to a relative tolerance).
    pub fn is_symmetric(&self, tol: f64) -> bool {
        let a = self.to_map();
        let scale = self.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter().all(|(&(i, j), &v)| (v - a.get(&(j, i)).copied().unwrap_or(0.0)).abs() <= tol * scale)
    }

    fn to_map(&self) -> std::collections::HashMap<(usize, usize), f64> {
        let p = &self.pattern;
        let mut m = std::collections::HashMap::new();
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                *m.entry((p.row_idx[k], j)).or_insert(0.0) += self.values[k];
            }
        }
        m
    }
}

/// Triplets collected in a fixed order by the assembler, their indices as 32-bit numbers (a run
/// refuses a model whose system would not fit them before it assembles anything:
/// [`MAX_ENTRIES`]).
#[derive(Debug, Default, Clone)]
pub struct Triplets {
    pub rows: Vec<u32>,
    pub cols: Vec<u32>,
    pub values: Vec<f64>,
}

/// The most equations, and the most triplets in one list, that the assembly can index.
pub const MAX_ENTRIES: usize = u32::MAX as usize;

impl Triplets {
    /// An empty list with room for `entries`.
    pub fn with_capacity(entries: usize) -> Triplets {
        Triplets {
            rows: Vec::with_capacity(entries),
            cols: Vec::with_capacity(entries),
            values: Vec::with_capacity(entries),
        }
    }

    /// Add A_ij += v.
    ///
    /// # Panics
    /// Beyond [`MAX_ENTRIES`] equations or entries, which a run refuses before it assembles
    /// (`analysis::context`), so that an index is never truncated.
    pub fn push(&mut self, i: usize, j: usize, v: f64) {
        assert!(
            i < MAX_ENTRIES && j < MAX_ENTRIES && self.values.len() < MAX_ENTRIES,
            "a system beyond 32-bit indices"
        );
        self.rows.push(i as u32);
        self.cols.push(j as u32);
        self.values.push(v);
    }
}

/// Keeps the pattern of the last assembly and refills values through the map while the triplet
/// indices stay the same.
///
/// A list whose every triplet falls on an entry of the kept pattern with the same row and column
/// refills it (a list that lost entries keeps them as explicit zeros: the same matrix); any other
/// list builds a new pattern. The map and each entry's column are kept as 32-bit numbers, not a copy
/// of the list's indices.
#[derive(Debug, Default)]
pub struct PatternCache {
    n: usize,
    pattern: Option<Arc<CscPattern>>,
    /// Triplet k → its entry.
    map: Vec<u32>,
    /// Each entry's column (its row is the pattern's).
    entry_col: Vec<u32>,
    /// How many times a pattern was computed.
    pub builds: usize,
}

impl PatternCache {
    /// Turn triplets into a matrix. Returns the matrix and whether the pattern is new.
    pub fn assemble(&mut self, n: usize, t: &Triplets) -> (CscMatrix, bool) {
        let same = self.refills(n, t);
        let pattern = match self.pattern.clone() {
            Some(pattern) if same => pattern,
            _ => {
                // the old pattern's arrays go before the new ones are made
                *self = PatternCache { builds: self.builds + 1, ..PatternCache::default() };
                let (pattern, map) = CscPattern::from_triplets(n, &t.rows, &t.cols);
                self.entry_col = vec![0; pattern.nnz()];
                for j in 0..n {
                    self.entry_col[pattern.col_ptr[j]..pattern.col_ptr[j + 1]].fill(j as u32);
                }
                let pattern = Arc::new(pattern);
                self.pattern = Some(pattern.clone());
                self.map = map;
                self.n = n;
                pattern
            }
        };
        let mut values = vec![0.0; pattern.nnz()];
        for (&k, v) in self.map.iter().zip(&t.values) {
            values[k as usize] += v;
        }
        (CscMatrix { pattern, values }, !same)
    }

    /// Whether every triplet of `t` falls, through the kept map, on an entry of its own row and
    /// column.
    fn refills(&self, n: usize, t: &Triplets) -> bool {
        let Some(pattern) = &self.pattern else { return false };
        self.n == n
            && self.map.len() == t.rows.len()
            && self.map.iter().zip(t.rows.iter().zip(&t.cols)).all(|(&e, (&i, &j))| {
                let e = e as usize;
                pattern.row_idx[e] == i as usize && self.entry_col[e] == j
            })
    }
}

/// A counting sort of `len` items by their column (`column(k)` below `n` for item `k`): the items
/// (`item(k)`) in column order, those of one column in the order they came, and where each
/// column's run starts (`n + 1` offsets). What a sparse matrix is built from, column by column,
/// without a sort of the whole list.
pub fn bucket_by_column<T: Copy + Default>(
    n: usize,
    len: usize,
    column: impl Fn(usize) -> usize,
    item: impl Fn(usize) -> T,
) -> (Vec<T>, Vec<usize>) {
    let mut start = vec![0usize; n + 1];
    for k in 0..len {
        start[column(k) + 1] += 1;
    }
    for j in 0..n {
        start[j + 1] += start[j];
    }
    let mut next = start[..n].to_vec();
    let mut bucketed = vec![T::default(); len];
    for k in 0..len {
        let j = column(k);
        bucketed[next[j]] = item(k);
        next[j] += 1;
    }
    (bucketed, start)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_principal_submatrix_keeps_its_entries_and_gives_back_the_others() {
        // a 4 × 4 matrix with entries a_ij = 10 i + j + 1 where i + j is even or i = j + 1
        let mut t = Triplets::default();
        for i in 0..4 {
            for j in 0..4 {
                if (i + j) % 2 == 0 || i == j + 1 {
                    t.push(i, j, (10 * i + j + 1) as f64);
                }
            }
        }
        let (a, _) = PatternCache::default().assemble(4, &t);
        // equations 0, 2 and 3 kept, as 0, 1 and 2
        let (sub, left_out) = a.principal_submatrix(&[Some(0), None, Some(1), Some(2)], 3);
        let kept = [0, 2, 3];
        let dense = sub.to_dense();
        let whole = a.to_dense();
        for (p, &i) in kept.iter().enumerate() {
            for (q, &j) in kept.iter().enumerate() {
                assert_eq!(dense[p][q], whole[i][j], "({i}, {j})");
            }
        }
        let mut expected: Vec<(usize, usize, f64)> = Vec::new();
        for j in 0..4 {
            for (i, row) in whole.iter().enumerate() {
                if (i == 1 || j == 1) && row[j] != 0.0 {
                    expected.push((i, j, row[j]));
                }
            }
        }
        assert_eq!(left_out, expected);
        assert_eq!(sub.pattern.nnz() + left_out.len(), a.pattern.nnz());
    }

    #[test]
    fn duplicates_are_summed_and_the_map_is_reused() {
        let mut t = Triplets::default();
        t.push(0, 0, 1.0);
        t.push(1, 0, 2.0);
        t.push(0, 0, 3.0);
        t.push(1, 1, 4.0);
        let mut cache = PatternCache::default();
        let (a, new) = cache.assemble(2, &t);
        assert!(new);
        assert_eq!(a.pattern.nnz(), 3);
        assert_eq!(a.to_dense(), vec![vec![4.0, 0.0], vec![2.0, 4.0]]);
        t.values = vec![1.0, 1.0, 1.0, 1.0];
        let (b, new) = cache.assemble(2, &t);
        assert!(!new);
        assert_eq!(cache.builds, 1);
        assert_eq!(b.to_dense(), vec![vec![2.0, 0.0], vec![1.0, 1.0]]);
    }

    /// A scrambled list with repeated positions and empty columns against the definition: the
    /// distinct (column, row) pairs in order, and each triplet mapped to its own pair's entry.
    #[test]
    fn a_scrambled_list_gives_each_distinct_position_once_in_order() {
        let n = 37;
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut draw = |m: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % m) as u32
        };
        // columns 5 and 6 left empty
        let (rows, cols): (Vec<u32>, Vec<u32>) = (0..2000)
            .map(|_| {
                let c = draw(n as u64 - 2);
                (draw(n as u64), if c >= 5 { c + 2 } else { c })
            })
            .unzip();
        let (pattern, map) = CscPattern::from_triplets(n, &rows, &cols);
        let distinct: std::collections::BTreeSet<(u32, u32)> = cols.iter().copied().zip(rows.iter().copied()).collect();
        assert_eq!(pattern.nnz(), distinct.len());
        let stored: Vec<(u32, u32)> = (0..n)
            .flat_map(|j| {
                let pattern = &pattern;
                (pattern.col_ptr()[j]..pattern.col_ptr()[j + 1]).map(move |e| (j as u32, pattern.row_idx()[e] as u32))
            })
            .collect();
        assert_eq!(stored, distinct.into_iter().collect::<Vec<_>>());
        for (k, &e) in map.iter().enumerate() {
            assert_eq!(stored[e as usize], (cols[k], rows[k]), "triplet {k}");
        }
    }

    #[test]
    fn a_list_with_an_entry_moved_builds_a_new_pattern() {
        let mut t = Triplets::default();
        t.push(0, 0, 1.0);
        t.push(1, 0, 2.0);
        t.push(1, 1, 4.0);
        let mut cache = PatternCache::default();
        cache.assemble(2, &t);
        // the same count of triplets, one of them in another column
        t.cols[1] = 1;
        let (a, new) = cache.assemble(2, &t);
        assert!(new);
        assert_eq!(cache.builds, 2);
        assert_eq!(a.to_dense(), vec![vec![1.0, 0.0], vec![0.0, 6.0]]);
        // a row moved in its column
        t.rows[1] = 0;
        let (b, new) = cache.assemble(2, &t);
        assert!(new);
        assert_eq!(b.to_dense(), vec![vec![1.0, 2.0], vec![0.0, 4.0]]);
    }
}
