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
    pub fn from_triplets(n: usize, rows: &[usize], cols: &[usize]) -> (CscPattern, Vec<usize>) {
        assert_eq!(rows.len(), cols.len());
        assert!(rows.iter().chain(cols).all(|&i| i < n), "triplet index out of range");
        // Sort by column, then by row inside each column; equal keys share one entry.
        let mut order: Vec<usize> = (0..rows.len()).collect();
        order.sort_unstable_by_key(|&k| (cols[k], rows[k]));
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(rows.len());
        let mut map = vec![0usize; rows.len()];
        let mut last: Option<(usize, usize)> = None;
        for &k in &order {
            let key = (cols[k], rows[k]);
            if last != Some(key) {
                row_idx.push(rows[k]);
                col_ptr[cols[k] + 1] += 1;
                last = Some(key);
            }
            map[k] = row_idx.len() - 1;
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

/// Triplets collected in a fixed order by the assembler.
#[derive(Debug, Default, Clone)]
pub struct Triplets {
    pub rows: Vec<usize>,
    pub cols: Vec<usize>,
    pub values: Vec<f64>,
}

impl Triplets {
    /// An empty list with room for `entries`.
    pub fn with_capacity(entries: usize) -> Triplets {
        Triplets {
            rows: Vec::with_capacity(entries),
            cols: Vec::with_capacity(entries),
            values: Vec::with_capacity(entries),
        }
    }

    pub fn push(&mut self, i: usize, j: usize, v: f64) {
        self.rows.push(i);
        self.cols.push(j);
        self.values.push(v);
    }
}

/// Keeps the pattern of the last assembly and refills values through the map while the triplet
/// indices stay the same.
///
/// The indices it compares with and the map are kept as 32-bit numbers (half the memory of the
/// triplets' own); a system of more than 2³² − 1 equations or entries is assembled afresh each
/// time instead.
#[derive(Debug, Default)]
pub struct PatternCache {
    n: usize,
    rows: Vec<u32>,
    cols: Vec<u32>,
    pattern: Option<Arc<CscPattern>>,
    map: Vec<u32>,
    /// How many times a pattern was computed.
    pub builds: usize,
}

impl PatternCache {
    /// Turn triplets into a matrix. Returns the matrix and whether the pattern is new.
    pub fn assemble(&mut self, n: usize, t: &Triplets) -> (CscMatrix, bool) {
        let compact = n <= u32::MAX as usize && t.rows.len() <= u32::MAX as usize;
        let equal = |kept: &[u32], now: &[usize]| {
            kept.len() == now.len() && kept.iter().zip(now).all(|(&a, &b)| a as usize == b)
        };
        let same = compact
            && self.pattern.is_some()
            && self.n == n
            && equal(&self.rows, &t.rows)
            && equal(&self.cols, &t.cols);
        if !same {
            // the old pattern's arrays go before the new ones are made
            *self = PatternCache { builds: self.builds + 1, ..PatternCache::default() };
            let (pattern, map) = CscPattern::from_triplets(n, &t.rows, &t.cols);
            if !compact {
                let mut values = vec![0.0; pattern.nnz()];
                for (&k, v) in map.iter().zip(&t.values) {
                    values[k] += v;
                }
                return (CscMatrix { pattern: Arc::new(pattern), values }, true);
            }
            self.pattern = Some(Arc::new(pattern));
            self.map = map.into_iter().map(|k| k as u32).collect();
            self.rows = t.rows.iter().map(|&i| i as u32).collect();
            self.cols = t.cols.iter().map(|&j| j as u32).collect();
            self.n = n;
        }
        let pattern = self.pattern.clone().expect("pattern was just built");
        let mut values = vec![0.0; pattern.nnz()];
        for (&k, v) in self.map.iter().zip(&t.values) {
            values[k as usize] += v;
        }
        (CscMatrix { pattern, values }, !same)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
