//! The blocked (TSQR) Householder QR of a tall regression matrix: the rows are cut into a fixed
//! number of blocks (independent of the thread count, so results are bit-identical for any number
//! of threads), each block is reduced to its `R` factor in chunks, and the block factors are
//! stacked and reduced once more.

use nalgebra::DMatrix;
use rayon::prelude::*;

/// Number of independent blocks of the TSQR (fixed: results do not depend on the thread count).
const BLOCKS: usize = 64;
/// Rows per chunk inside a block.
const CHUNK: usize = 512;

/// The `k × k` upper-triangular `R` of the `n × k` matrix whose row `i` is written by
/// `fill(row, i)`.
pub(super) fn r_factor(
    n: usize,
    k: usize,
    fill: &(dyn Fn(&mut [f64], usize) + Sync),
) -> DMatrix<f64> {
    let blocks = BLOCKS.min(n.div_ceil(CHUNK));
    let bounds: Vec<(usize, usize)> = (0..blocks)
        .map(|b| (b * n / blocks, (b + 1) * n / blocks))
        .collect();
    let rs: Vec<DMatrix<f64>> = bounds
        .par_iter()
        .map(|&(a, b)| block_r(a, b, k, fill))
        .collect();
    let mut stack = DMatrix::zeros(k * rs.len(), k);
    for (b, r) in rs.iter().enumerate() {
        stack.view_mut((b * k, 0), (r.nrows(), k)).copy_from(r);
    }
    qr_r(stack, k)
}

/// Upper-triangular `R` (k×k) of rows `a..b` via chunked Householder QR.
fn block_r(
    a: usize,
    b: usize,
    k: usize,
    fill: &(dyn Fn(&mut [f64], usize) + Sync),
) -> DMatrix<f64> {
    let mut r: Option<DMatrix<f64>> = None;
    let mut row = vec![0.0; k];
    let mut start = a;
    while start < b {
        let end = (start + CHUNK).min(b);
        let top = r.as_ref().map_or(0, DMatrix::nrows);
        let mut s = DMatrix::zeros(top + end - start, k);
        if let Some(r) = &r {
            s.view_mut((0, 0), (top, k)).copy_from(r);
        }
        for i in start..end {
            fill(&mut row, i);
            for (j, v) in row.iter().enumerate() {
                s[(top + i - start, j)] = *v;
            }
        }
        r = Some(qr_r(s, k));
        start = end;
    }
    r.unwrap_or_else(|| DMatrix::zeros(0, k))
}

/// `R` factor of an m×k matrix, padded to k×k when m < k.
fn qr_r(s: DMatrix<f64>, k: usize) -> DMatrix<f64> {
    let r = s.qr().r();
    if r.nrows() == k {
        return r;
    }
    let mut full = DMatrix::zeros(k, k);
    full.view_mut((0, 0), (r.nrows(), k)).copy_from(&r);
    full
}
