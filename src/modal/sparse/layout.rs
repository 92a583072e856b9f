//! The interleaved row layout of the 8-wide kernels ([`super::kernels`]): up to eight columns
//! of a faer block gathered into rows of eight (through a permutation when the factor has one)
//! and scattered back, with per-thread scratch so that the thousands of calls of one solve do
//! not allocate; and the column slices of faer matrices the block kernels read.

use faer::{MatMut, MatRef};

/// Columns c0..c0 + w (w ≤ 8) of `x` as the interleaved rows of the 8-wide kernels: row
/// inv[o] holds x[o, c0..c0 + w] (row o without a permutation), zero-padded to eight.
///
/// One pass over the original rows: every column is read contiguously and every row of the
/// kernel's layout is written whole, once (a column-at-a-time transpose wrote each 64-byte
/// row eight times and cost more than the sparse product it fed).
pub(super) fn gather_rows(
    x: MatRef<'_, f64>,
    c0: usize,
    w: usize,
    inv: Option<&[usize]>,
    rows: &mut [[f64; 8]],
) {
    let n = rows.len();
    let cols: Vec<&[f64]> = (0..w).map(|c| column(x, c0 + c)).collect();
    let row_of = |o: usize| match inv {
        Some(inv) => inv[o],
        None => o,
    };
    if w == 8 {
        let c: [&[f64]; 8] = std::array::from_fn(|k| &cols[k][..n]);
        for o in 0..n {
            rows[row_of(o)] = [
                c[0][o], c[1][o], c[2][o], c[3][o], c[4][o], c[5][o], c[6][o], c[7][o],
            ];
        }
    } else {
        for o in 0..n {
            let mut r = [0.0; 8];
            for (k, col) in cols.iter().enumerate() {
                r[k] = col[o];
            }
            rows[row_of(o)] = r;
        }
    }
}

/// The inverse of [`gather_rows`]: the first w values of every row back into columns
/// c0..c0 + w of `y`, through the same permutation (each row read whole, each column
/// written contiguously).
pub(super) fn scatter_rows(
    rows: &[[f64; 8]],
    c0: usize,
    w: usize,
    inv: Option<&[usize]>,
    mut y: MatMut<'_, f64>,
) {
    let n = rows.len();
    let row_of = |o: usize| match inv {
        Some(inv) => inv[o],
        None => o,
    };
    let mut cols = columns_mut(y.as_mut().subcols_mut(c0, w));
    if w == 8 {
        let [c0, c1, c2, c3, c4, c5, c6, c7] = &mut cols[..] else {
            unreachable!("eight columns")
        };
        let (c0, c1, c2, c3) = (&mut c0[..n], &mut c1[..n], &mut c2[..n], &mut c3[..n]);
        let (c4, c5, c6, c7) = (&mut c4[..n], &mut c5[..n], &mut c6[..n], &mut c7[..n]);
        for o in 0..n {
            let r = &rows[row_of(o)];
            c0[o] = r[0];
            c1[o] = r[1];
            c2[o] = r[2];
            c3[o] = r[3];
            c4[o] = r[4];
            c5[o] = r[5];
            c6[o] = r[6];
            c7[o] = r[7];
        }
    } else {
        for o in 0..n {
            let r = &rows[row_of(o)];
            for (k, col) in cols.iter_mut().enumerate() {
                col[o] = r[k];
            }
        }
    }
}

/// A column of a faer matrix as a slice (faer stores columns contiguously).
pub(super) fn column(x: MatRef<'_, f64>, c: usize) -> &[f64] {
    x.col(c)
        .try_as_col_major()
        .expect("faer matrices are column-major")
        .as_slice()
}

/// Per-thread scratch of the 8-wide kernels, reused across calls: two n × 8 interleaved
/// blocks. Allocating them per call (about 1 MB on the 60-satellite stack, thousands of calls)
/// cost page faults and zeroing, 5% of the solve.
struct Scratch {
    a: Vec<[f64; 8]>,
    b: Vec<[f64; 8]>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = const {
        std::cell::RefCell::new(Scratch { a: Vec::new(), b: Vec::new() })
    };
}

/// Runs `f` on this thread's scratch, both blocks n rows long (contents unspecified).
pub(super) fn with_scratch<R>(
    n: usize,
    f: impl FnOnce(&mut [[f64; 8]], &mut [[f64; 8]]) -> R,
) -> R {
    SCRATCH.with(|s| {
        let mut s = s.borrow_mut();
        let Scratch { a, b } = &mut *s;
        a.resize(n, [0.0; 8]);
        b.resize(n, [0.0; 8]);
        f(&mut a[..n], &mut b[..n])
    })
}

/// The columns of a faer matrix as mutable slices.
pub(super) fn columns_mut(x: MatMut<'_, f64>) -> Vec<&mut [f64]> {
    x.col_iter_mut()
        .map(|c| {
            c.try_as_col_major_mut()
                .expect("faer matrices are column-major")
                .as_slice_mut()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// Gathering puts x[o, c0 + k] in row inv[o], lane k, zero-padded; scattering through the
    /// same permutation restores the columns exactly (a copy, no arithmetic).
    #[test]
    fn gather_then_scatter_is_the_identity_through_a_permutation() {
        let n = 7;
        let inv = [3, 0, 6, 1, 5, 2, 4];
        let x = Mat::<f64>::from_fn(n, 11, |i, j| (100 * i + j) as f64);
        for (c0, w) in [(0, 8), (8, 3)] {
            let mut rows = vec![[f64::NAN; 8]; n];
            gather_rows(x.as_ref(), c0, w, Some(&inv), &mut rows);
            for o in 0..n {
                for k in 0..8 {
                    let want = if k < w { x[(o, c0 + k)] } else { 0.0 };
                    assert_eq!(rows[inv[o]][k], want);
                }
            }
            let mut y = Mat::<f64>::zeros(n, 11);
            scatter_rows(&rows, c0, w, Some(&inv), y.as_mut());
            for o in 0..n {
                for k in 0..w {
                    assert_eq!(y[(o, c0 + k)], x[(o, c0 + k)]);
                }
            }
        }
    }

    #[test]
    fn scratch_has_the_length_asked_for() {
        assert_eq!(with_scratch(5, |a, b| (a.len(), b.len())), (5, 5));
        assert_eq!(with_scratch(2, |a, b| (a.len(), b.len())), (2, 2));
    }
}
