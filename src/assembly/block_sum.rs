//! Per-DOF sums of element blocks' contributions, in parallel and independent of the number of
//! threads: the internal forces and the matrix-free products are made of them.

use nalgebra::DMatrix;

/// Sum per-DOF contributions of element blocks over `n` DOFs, in parallel: the blocks are cut into a
/// fixed number of runs (not one per thread), each summed into a vector of its own, and the vectors
/// are added in order, so that the result does not depend on the number of threads. The runs' length
/// is set by the first `leading` blocks alone (the blocks after them fall into runs of the same
/// length): a sum over those blocks cuts them where a sum over them and more blocks does, so that
/// what the leading blocks add up to is the same to the last bit in both.
pub fn par_block_sum(
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    leading: usize,
    n: usize,
    each: impl Fn(usize, &[usize], &DMatrix<f64>, &mut [f64]) + Sync,
) -> Vec<f64> {
    use rayon::prelude::*;
    const RUNS: usize = 4;
    const SEQUENTIAL_BELOW: usize = 4096;
    let leading = leading.min(blocks.len());
    let run = if leading < SEQUENTIAL_BELOW { leading.max(1) } else { leading.div_ceil(RUNS) };
    let parts: Vec<Vec<f64>> = blocks
        .par_chunks(run)
        .enumerate()
        .map(|(c, chunk)| {
            let mut f = vec![0.0; n];
            for (i, (dl, k)) in chunk.iter().enumerate() {
                each(c * run + i, dl, k, &mut f);
            }
            f
        })
        .collect();
    let mut parts = parts.into_iter();
    let mut total = parts.next().unwrap_or_else(|| vec![0.0; n]);
    for part in parts {
        for (t, p) in total.iter_mut().zip(&part) {
            *t += p;
        }
    }
    total
}
