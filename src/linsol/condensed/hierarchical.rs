//! A hierarchical factorisation of T, the dense part of the kept system: HODLR (hierarchically
//! off-diagonal low-rank), factorised by the Sherman–Morrison–Woodbury identity at every level.
//!
//! T holds the soil's Schur complement on the interface's lines, and the Schur complement of an
//! elastic body onto a line is data-sparse: a block coupling one stretch of the line to another is
//! of low rank. Ordered along the lines and bisected,
//!
//! ```text
//! T = [T₁₁     U₁V₁ᵀ]     T⁻¹ b: y = diag(T₁₁, T₂₂)⁻¹ b,  x = y − Ũ K⁻¹ [V₁ᵀ y₂; V₂ᵀ y₁]
//!     [U₂V₂ᵀ   T₂₂  ]     Ũ = diag(T₁₁⁻¹U₁, T₂₂⁻¹U₂),     K = [I  V₁ᵀ Ũ₂; V₂ᵀ Ũ₁  I]
//! ```
//!
//! with T₁₁ and T₂₂ split again down to leaves of at most [`LEAF`] unknowns, factorised densely.
//! For d unknowns and ranks k it costs O(d²·k) to compress (each block once, by a randomised range
//! finder) and O(d·k²·log²d) to factorise, against 2d³/3 for a dense LU: on the 4·10⁵-unknown
//! pull-out's T (d = 2530) the blocks of 1265 have rank 58 at 10⁻¹⁰ of ‖T‖.
//!
//! The factors are T's to [`TOLERANCE`], not exact: they precondition the kept system's solves,
//! which are refined against M itself to the same residual as a direct solve (`updated_lu.rs`).
//!
//! **The order.** The unknowns are ordered by reverse Cuthill–McKee on T's strong couplings (an
//! entry of at least [`STRONG`] of its row's largest off the diagonal), which follows each
//! interface line. T is a saddle-point matrix: a multiplier's row has a zero diagonal, and a block
//! holding it without the unknown it constrains is singular. So each multiplier is first paired
//! with the unknown it couples to most strongly (each unknown taken once), a pair is never split,
//! and every block on the diagonal holds whole pairs.

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::reborrow::ReborrowMut;
use faer::{Mat, MatMut, MatRef};
use std::collections::VecDeque;

/// T is factorised hierarchically from this order up, densely below it. Measured on the
/// large-slip pull-out (docs/performance.md): at d = 2530 (4·10⁵ unknowns) a factorisation takes
/// 0.37–0.44 s against 0.43 s for the dense LU, no gain; at d = 5055 (1.6·10⁶) 1.03–1.49 s against
/// about 1.5 s.
pub const FROM_ORDER: usize = 4000;
/// The largest block factorised densely.
pub const LEAF: usize = 320;
/// Each off-diagonal block is compressed to this share of ‖T‖_F (in the 2-norm of its error).
pub const TOLERANCE: f64 = 1e-12;
/// An off-diagonal entry is a strong coupling, for the order, at this share of its row's largest.
const STRONG: f64 = 1e-2;

/// T's hierarchical factors.
#[derive(Debug)]
pub struct Hierarchical {
    /// T's unknowns in the factors' order: position k of the factors is `order[k]` of T.
    order: Vec<usize>,
    root: Node,
    /// The largest rank of an off-diagonal block.
    #[cfg_attr(not(test), allow(dead_code))]
    pub largest_rank: usize,
}

#[derive(Debug)]
enum Node {
    Leaf(PartialPivLu<f64>),
    Split(Box<Split>),
}

#[derive(Debug)]
struct Split {
    /// The order of the first block.
    first_order: usize,
    first: Node,
    second: Node,
    /// T₁₂ = U₁V₁ᵀ and T₂₁ = U₂V₂ᵀ, held as Ũ₁ = T₁₁⁻¹U₁, V₁, Ũ₂ = T₂₂⁻¹U₂, V₂.
    u1: Mat<f64>,
    v1: Mat<f64>,
    u2: Mat<f64>,
    v2: Mat<f64>,
    capacitance: PartialPivLu<f64>,
}

impl Hierarchical {
    /// The hierarchical factors of `t`; none when its order cannot be found (a multiplier with no
    /// unknown left to pair with) or a block is singular.
    pub fn of(t: MatRef<'_, f64>) -> Option<Hierarchical> {
        let d = t.nrows();
        let (order, starts) = line_order(t)?;
        let norm = t.norm_l2();
        let mut largest_rank = 0;
        let mut build =
            Build { t, order: &order, starts: &starts, tolerance: TOLERANCE * norm, largest_rank: &mut largest_rank };
        let root = build.node(0, d, 1)?;
        Some(Hierarchical { order, root, largest_rank })
    }

    /// T⁻¹ b for the factors' T, in place (`b`: rows in T's order).
    pub fn solve_in_place(&self, mut b: MatMut<'_, f64>) {
        let columns = b.ncols();
        let mut x = Mat::from_fn(self.order.len(), columns, |k, c| b[(self.order[k], c)]);
        self.root.solve_in_place(x.as_mut());
        for (k, &i) in self.order.iter().enumerate() {
            for c in 0..columns {
                b[(i, c)] = x[(k, c)];
            }
        }
    }
}

impl Node {
    fn solve_in_place(&self, mut x: MatMut<'_, f64>) {
        match self {
            Node::Leaf(lu) => lu.solve_in_place(x.rb_mut()),
            Node::Split(s) => {
                let (mut x1, mut x2) = x.rb_mut().split_at_row_mut(s.first_order);
                s.first.solve_in_place(x1.rb_mut());
                s.second.solve_in_place(x2.rb_mut());
                let (k1, k2) = (s.v1.ncols(), s.v2.ncols());
                let mut z = Mat::<f64>::zeros(k1 + k2, x1.ncols());
                z.as_mut().subrows_mut(0, k1).copy_from(s.v1.transpose() * x2.as_ref());
                z.as_mut().subrows_mut(k1, k2).copy_from(s.v2.transpose() * x1.as_ref());
                s.capacitance.solve_in_place(z.as_mut());
                x1 -= &s.u1 * z.as_ref().subrows(0, k1);
                x2 -= &s.u2 * z.as_ref().subrows(k1, k2);
            }
        }
    }
}

/// What building the tree reads.
struct Build<'a> {
    t: MatRef<'a, f64>,
    order: &'a [usize],
    /// The positions (in the factors' order) where a pair or a lone unknown starts.
    starts: &'a [usize],
    tolerance: f64,
    largest_rank: &'a mut usize,
}

impl Build<'_> {
    /// The node of the unknowns `lo..hi` of the factors' order.
    fn node(&mut self, lo: usize, hi: usize, seed: u64) -> Option<Node> {
        let split = if hi - lo > LEAF { self.split_near_middle(lo, hi) } else { None };
        let Some(mid) = split else {
            let block = self.gather(lo..hi, lo..hi);
            return Some(Node::Leaf(block.partial_piv_lu()));
        };
        let g1 = self.gather(lo..mid, mid..hi);
        // (the blocks' ranks are alike: the first block of vectors is the last rank found)
        let (u1, v1) = compress(g1, self.tolerance, 2 * seed, *self.largest_rank)?;
        let (u2, v2) = compress(self.gather(mid..hi, lo..mid), self.tolerance, 2 * seed + 1, u1.ncols())?;
        *self.largest_rank = (*self.largest_rank).max(u1.ncols()).max(u2.ncols());
        let first = self.node(lo, mid, 2 * seed)?;
        let second = self.node(mid, hi, 2 * seed + 1)?;
        let mut u1 = u1;
        let mut u2 = u2;
        first.solve_in_place(u1.as_mut());
        second.solve_in_place(u2.as_mut());
        let (k1, k2) = (u1.ncols(), u2.ncols());
        let mut k = Mat::<f64>::identity(k1 + k2, k1 + k2);
        k.as_mut().submatrix_mut(0, k1, k1, k2).copy_from(v1.transpose() * &u2);
        k.as_mut().submatrix_mut(k1, 0, k2, k1).copy_from(v2.transpose() * &u1);
        let finite = |m: &Mat<f64>| m.col_iter().all(|c| c.iter().all(|v| v.is_finite()));
        if !finite(&u1) || !finite(&u2) || !finite(&k) {
            return None;
        }
        let capacitance = k.partial_piv_lu();
        Some(Node::Split(Box::new(Split { first_order: mid - lo, first, second, u1, v1, u2, v2, capacitance })))
    }

    /// The start of a pair or lone unknown nearest the middle of `lo..hi`, inside it.
    fn split_near_middle(&self, lo: usize, hi: usize) -> Option<usize> {
        let middle = (lo + hi) / 2;
        let at = self.starts.partition_point(|&s| s < middle);
        [at.checked_sub(1), Some(at)]
            .into_iter()
            .flatten()
            .filter_map(|i| self.starts.get(i).copied())
            .filter(|&s| s > lo && s < hi)
            .min_by_key(|&s| s.abs_diff(middle))
    }

    fn gather(&self, rows: std::ops::Range<usize>, columns: std::ops::Range<usize>) -> Mat<f64> {
        let (r0, c0) = (rows.start, columns.start);
        Mat::from_fn(rows.len(), columns.len(), |i, j| self.t[(self.order[r0 + i], self.order[c0 + j])])
    }
}

/// B ≈ U Vᵀ with ‖B − U Vᵀ‖₂ ≤ about `tolerance`: an adaptive randomised range finder (Halko,
/// Martinsson and Tropp 2011, algorithm 4.2, by blocks of [`BLOCK`] vectors): each block's images
/// B·Ω, less their part in the range found so far, are the a-posteriori estimate of the error
/// (their §4.3: ‖(I − QQᵀ)B‖₂ ≤ 10·√(2/π)·maxᵢ ‖(I − QQᵀ)B ωᵢ‖ but with probability 10⁻ᴮᴸᴼᶜᴷ)
/// and, while it is not met, extend the range. The range Q found, Qᵀ B is truncated by its SVD. A
/// block whose rank would be half its size or more is truncated by its own SVD.
fn compress(b: Mat<f64>, tolerance: f64, seed: u64, first_block: usize) -> Option<(Mat<f64>, Mat<f64>)> {
    const BLOCK: usize = 16;
    let (m, n) = (b.nrows(), b.ncols());
    let full = m.min(n);
    // a block whose rank is a large share of its size: its own SVD, truncated
    let truncated = |b: Mat<f64>| {
        let svd = b.thin_svd().ok()?;
        let s = svd.S().column_vector();
        let rank = (0..s.nrows()).filter(|&i| s[i] > tolerance).count();
        let u = Mat::from_fn(m, rank, |i, j| svd.U()[(i, j)] * s[j]);
        Some((u, svd.V().subcols(0, rank).to_owned()))
    };
    let mut random = Random(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (m as u64) << 32 ^ n as u64);
    let estimate = 10.0 * (2.0 / std::f64::consts::PI).sqrt();
    let mut q = Mat::<f64>::zeros(m, 0);
    loop {
        let block = if q.ncols() == 0 { first_block.max(BLOCK) } else { BLOCK };
        if 2 * (q.ncols() + block) >= full {
            return truncated(b);
        }
        let mut y = product(b.as_ref(), random.matrix(n, block).as_ref());
        // (I − QQᵀ) twice: once is not orthogonal enough in floating point once Q is large
        for _ in 0..2 {
            let qty = product(q.transpose(), y.as_ref());
            y -= product(q.as_ref(), qty.as_ref());
        }
        let largest = y.col_iter().map(|c| c.norm_l2()).fold(0.0, f64::max);
        if !largest.is_finite() {
            return None;
        }
        if estimate * largest <= tolerance {
            break;
        }
        // the block orthonormalised (modified Gram–Schmidt) and appended; a vector with nothing
        // left beside the others is dropped
        let mut kept: Vec<Vec<f64>> = Vec::with_capacity(block);
        for j in 0..block {
            let mut v: Vec<f64> = y.col(j).iter().copied().collect();
            let before = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            for _ in 0..2 {
                for w in &kept {
                    let dot: f64 = v.iter().zip(w).map(|(a, b)| a * b).sum();
                    v.iter_mut().zip(w).for_each(|(a, b)| *a -= dot * b);
                }
            }
            let after = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if after > 1e-8 * before && after > 0.0 {
                v.iter_mut().for_each(|x| *x /= after);
                kept.push(v);
            }
        }
        let k = q.ncols();
        let mut wider = Mat::<f64>::zeros(m, k + kept.len());
        wider.as_mut().subcols_mut(0, k).copy_from(&q);
        for (j, v) in kept.iter().enumerate() {
            wider.col_mut(k + j).iter_mut().zip(v).for_each(|(a, b)| *a = *b);
        }
        q = wider;
    }
    if q.ncols() == 0 {
        return Some((Mat::zeros(m, 0), Mat::zeros(n, 0)));
    }
    let z = product(q.transpose(), b.as_ref());
    let svd = z.thin_svd().ok()?;
    let s = svd.S().column_vector();
    let rank = (0..s.nrows()).filter(|&i| s[i] > tolerance).count();
    let u = product(q.as_ref(), svd.U().subcols(0, rank));
    let u = Mat::from_fn(m, rank, |i, j| u[(i, j)] * s[j]);
    Some((u, svd.V().subcols(0, rank).to_owned()))
}

/// a·b, on the threads when it is large.
fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::zeros(a.nrows(), b.ncols());
    let flops = a.nrows() * a.ncols() * b.ncols();
    let par = if flops > 1 << 22 { faer::get_global_parallelism() } else { faer::Par::Seq };
    faer::linalg::matmul::matmul(out.as_mut(), faer::Accum::Replace, a, b, 1.0, par);
    out
}

/// Uniform numbers in [−1, 1) from SplitMix64: the same factors for the same T on every run.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn matrix(&mut self, rows: usize, columns: usize) -> Mat<f64> {
        Mat::from_fn(rows, columns, |_, _| self.next())
    }
}

/// T's unknowns in the order of the factors, and where each pair or lone unknown starts in it
/// (module comment); none when a multiplier (a zero diagonal) has no unknown left to pair with.
fn line_order(t: MatRef<'_, f64>) -> Option<(Vec<usize>, Vec<usize>)> {
    let d = t.nrows();
    const NONE: usize = usize::MAX;
    // each multiplier's partner: the unknown with a nonzero diagonal it couples to most strongly
    let mut group = (0..d).collect::<Vec<usize>>();
    let mut taken: Vec<bool> = (0..d).map(|i| t[(i, i)] == 0.0).collect();
    for i in (0..d).filter(|&i| t[(i, i)] == 0.0) {
        let partner = (0..d)
            .filter(|&j| !taken[j])
            .map(|j| (j, t[(i, j)].abs().max(t[(j, i)].abs())))
            .filter(|&(_, v)| v > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1))?
            .0;
        taken[partner] = true;
        group[i] = partner;
    }
    // the groups (a pair or a lone unknown), numbered by their representative
    let mut number = vec![NONE; d];
    let mut members: Vec<Vec<usize>> = Vec::new();
    for i in 0..d {
        let r = group[i];
        if number[r] == NONE {
            number[r] = members.len();
            members.push(Vec::new());
        }
    }
    for i in 0..d {
        members[number[group[i]]].push(i);
    }
    let g = members.len();
    // the strong couplings between groups, by rows of T (and, for symmetry, their transposes)
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); g];
    for j in 0..d {
        let column = t.col(j);
        // column j of T is row j of Tᵀ: a coupling strong in either direction counts
        let largest = (0..d).filter(|&i| i != j).map(|i| column[i].abs()).fold(0.0, f64::max);
        if largest == 0.0 {
            continue;
        }
        for i in (0..d).filter(|&i| i != j && column[i].abs() >= STRONG * largest) {
            let (a, b) = (number[group[i]], number[group[j]]);
            if a != b {
                neighbours[a].push(b);
                neighbours[b].push(a);
            }
        }
    }
    for n in &mut neighbours {
        n.sort_unstable();
        n.dedup();
    }
    let groups = reverse_cuthill_mckee(&neighbours);
    let mut order = Vec::with_capacity(d);
    let mut starts = Vec::with_capacity(g);
    for &k in &groups {
        starts.push(order.len());
        order.extend_from_slice(&members[k]);
    }
    Some((order, starts))
}

/// Reverse Cuthill–McKee on a graph given by its neighbour lists: each component from a
/// pseudo-peripheral node (the last reached of a breadth-first search from its node of least
/// degree), neighbours taken in increasing degree.
fn reverse_cuthill_mckee(neighbours: &[Vec<usize>]) -> Vec<usize> {
    let n = neighbours.len();
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|&v| neighbours[v].len());
    let breadth_first = |start: usize, mark: &mut Vec<bool>, out: &mut Vec<usize>| {
        let mut queue = VecDeque::from([start]);
        mark[start] = true;
        while let Some(v) = queue.pop_front() {
            out.push(v);
            let mut next: Vec<usize> = neighbours[v].iter().copied().filter(|&w| !mark[w]).collect();
            next.sort_by_key(|&w| neighbours[w].len());
            for w in next {
                mark[w] = true;
                queue.push_back(w);
            }
        }
    };
    for &seed in &by_degree {
        if placed[seed] {
            continue;
        }
        // the far end of the component from its seed
        let mut probe_mark = placed.clone();
        let mut reached = Vec::new();
        breadth_first(seed, &mut probe_mark, &mut reached);
        let start = *reached.last().unwrap_or(&seed);
        let mut component = Vec::new();
        breadth_first(start, &mut placed, &mut component);
        order.extend(component.into_iter().rev());
    }
    order
}

#[cfg(test)]
mod tests {
    //! The factors of a saddle-point matrix shaped as T: a soil line's smooth kernel, its
    //! multipliers each on one soil unknown.
    use super::*;

    /// T of `soil` unknowns on a line (a kernel decaying with distance, diagonally dominant) and a
    /// multiplier on every third of them, its unknowns shuffled: a multiplier row with a zero
    /// diagonal and one entry, so that any diagonal block holding it without its unknown is singular.
    fn saddle(soil: usize) -> Mat<f64> {
        let multipliers = soil / 3;
        let d = soil + multipliers;
        // a fixed shuffle, so that the order has to be found
        let place: Vec<usize> = {
            let mut p: Vec<usize> = (0..d).collect();
            let mut r = Random(7);
            for i in (1..d).rev() {
                let j = ((r.next() + 1.0) * 0.5 * (i + 1) as f64) as usize % (i + 1);
                p.swap(i, j);
            }
            p
        };
        let mut t = Mat::zeros(d, d);
        for i in 0..soil {
            for j in 0..soil {
                let r = (i as f64 - j as f64).abs();
                t[(place[i], place[j])] = if i == j { 4.0 } else { 1.0 / (1.0 + r * r) };
            }
        }
        for k in 0..multipliers {
            let (row, on) = (place[soil + k], place[3 * k + 1]);
            t[(row, on)] = 2.0;
            t[(on, row)] = 2.0;
        }
        t
    }

    #[test]
    fn a_shuffled_saddle_point_line_is_factorised_to_its_tolerance_with_low_ranks() {
        let t = saddle(900);
        let h = Hierarchical::of(t.as_ref()).expect("factors");
        let b = Mat::from_fn(t.nrows(), 2, |i, c| ((i * 3 + c) as f64 * 0.41).sin());
        let mut x = b.clone();
        h.solve_in_place(x.as_mut());
        let residual = (&b - &t * &x).norm_l2() / b.norm_l2();
        // the factors are T's to TOLERANCE of ‖T‖; T's condition number here is about 10
        assert!(residual < 1e-9, "relative residual {residual}");
        // a smooth kernel on a line: its blocks far below their size in rank
        assert!(h.largest_rank < 80, "largest rank {}", h.largest_rank);
    }

    #[test]
    fn a_multiplier_with_nothing_to_pair_with_is_refused() {
        // two multipliers on the one unknown with a diagonal
        let t = Mat::from_fn(3, 3, |i, j| match (i, j) {
            (0, 0) => 2.0,
            (0, _) | (_, 0) => 1.0,
            _ => 0.0,
        });
        assert!(Hierarchical::of(t.as_ref()).is_none());
    }
}
