//! The kernels of the Lanczos iteration, each with a plain, an AVX2 and an AVX-512 build of
//! the same source: the two sparse ones on rows of eight interleaved right-hand sides, and the
//! block normalisation's Gram matrix and triangular product on column slices.
//!
//! [`simd_dispatch!`] picks the widest build the CPU supports at run time.

/// Calls a kernel through its AVX-512 or AVX2 build when the CPU has one (the crate itself
/// targets baseline x86-64, i.e. SSE2). Rust never contracts a·b + c into an FMA, so every
/// path gives bitwise the same result; only the register width changes. The interleaved
/// 8-wide rows of the two sparse kernels fill one AVX-512 register.
macro_rules! simd_dispatch {
    ($kernel:ident($($arg:expr),*)) => {{
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has AVX-512F, the only feature this build enables.
                unsafe { $crate::modal::sparse::kernels::avx512::$kernel($($arg),*) }
            } else if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2, the only feature this build enables.
                unsafe { $crate::modal::sparse::kernels::avx2::$kernel($($arg),*) }
            } else {
                $crate::modal::sparse::kernels::$kernel($($arg),*)
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            $crate::modal::sparse::kernels::$kernel($($arg),*)
        }
    }};
}
pub(super) use simd_dispatch;

/// y_i = Σ_r A_ir·x_r over the rows of a symmetric CSC matrix (column i = row i).
#[inline(always)]
pub fn spmm_rows(
    col_ptr: &[usize],
    row_idx: &[usize],
    val: &[f64],
    x: &[[f64; 8]],
    y: &mut [[f64; 8]],
) {
    for (i, yi) in y.iter_mut().enumerate() {
        let mut acc = [0.0f64; 8];
        let (lo, hi) = (col_ptr[i], col_ptr[i + 1]);
        for (&r, &v) in row_idx[lo..hi].iter().zip(&val[lo..hi]) {
            let xs = &x[r];
            for k in 0..8 {
                acc[k] += v * xs[k];
            }
        }
        *yi = acc;
    }
}

/// x ← L⁻ᵀ·D⁻¹·L⁻¹·x for faer's simplicial LDLᵀ (CSC, D first in every column).
#[inline(always)]
pub fn ldlt_sweeps(cp: &[usize], ri: &[usize], l: &[f64], x: &mut [[f64; 8]]) {
    let n = x.len();
    for j in 0..n {
        let xj = x[j];
        let (a, b) = (cp[j] + 1, cp[j + 1]);
        for (&r, &v) in ri[a..b].iter().zip(&l[a..b]) {
            let xr = &mut x[r];
            for k in 0..8 {
                xr[k] -= v * xj[k];
            }
        }
    }
    for j in (0..n).rev() {
        let mut acc = x[j];
        let d = l[cp[j]];
        for v in acc.iter_mut() {
            *v /= d;
        }
        let (a, b) = (cp[j] + 1, cp[j + 1]);
        for (&r, &v) in ri[a..b].iter().zip(&l[a..b]) {
            let xr = &x[r];
            for k in 0..8 {
                acc[k] -= v * xr[k];
            }
        }
        x[j] = acc;
    }
}

/// Row chunk of the two block kernels below: 256 rows of up to 16 columns stay in L1.
const CHUNK: usize = 256;

/// g = Xᵀ·Y (p × p, row-major) for n × p column sets, p ≤ 16, upper triangle computed
/// and mirrored. Eight lane sums per entry, added in a fixed order: the result does not
/// depend on the instruction set.
#[inline(always)]
pub fn gram_sym(x: &[&[f64]], y: &[&[f64]], g: &mut [f64]) {
    let p = x.len();
    let n = x.first().map_or(0, |c| c.len());
    let mut acc = [[0.0f64; 8]; 136];
    for s in (0..n).step_by(CHUNK) {
        let e = (s + CHUNK).min(n);
        let mut idx = 0;
        for a in 0..p {
            let xa = &x[a][s..e];
            for yb in &y[a..p] {
                let yb = &yb[s..e];
                let lanes = &mut acc[idx];
                let mut xc = xa.chunks_exact(8);
                let mut yc = yb.chunks_exact(8);
                for (xv, yv) in (&mut xc).zip(&mut yc) {
                    for k in 0..8 {
                        lanes[k] += xv[k] * yv[k];
                    }
                }
                for (k, (xv, yv)) in xc.remainder().iter().zip(yc.remainder()).enumerate() {
                    lanes[k] += xv * yv;
                }
                idx += 1;
            }
        }
    }
    let mut idx = 0;
    for a in 0..p {
        for b in a..p {
            let l = &acc[idx];
            let v = ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]));
            g[a * p + b] = v;
            g[b * p + a] = v;
            idx += 1;
        }
    }
}

/// X ← X·U in place for an upper-triangular p × p U (row-major), p ≤ 16: column j
/// becomes U_jj·x_j + Σ_{k<j} U_kj·x_k, so the columns are rewritten from the last.
#[inline(always)]
pub fn mul_upper(x: &mut [&mut [f64]], u: &[f64]) {
    let p = x.len();
    if p == 8 {
        return mul_upper8(x, u);
    }
    let n = x.first().map_or(0, |c| c.len());
    let mut t = [0.0f64; CHUNK];
    for s in (0..n).step_by(CHUNK) {
        let e = (s + CHUNK).min(n);
        let t = &mut t[..e - s];
        for j in (0..p).rev() {
            let (lo, hi) = x.split_at_mut(j);
            let xj = &mut hi[0][s..e];
            let ujj = u[j * p + j];
            for (ti, xi) in t.iter_mut().zip(xj.iter()) {
                *ti = ujj * xi;
            }
            for (k, xk) in lo.iter().enumerate() {
                let ukj = u[k * p + j];
                for (ti, xi) in t.iter_mut().zip(&xk[s..e]) {
                    *ti += ukj * xi;
                }
            }
            xj.copy_from_slice(t);
        }
    }
}

/// [`mul_upper`] for the Lanczos block width: eight rows at a time, all eight columns
/// in registers, so every value is loaded and stored once (same sums, same order).
#[inline(always)]
fn mul_upper8(x: &mut [&mut [f64]], u: &[f64]) {
    let n = x[0].len();
    let mut uu = [[0.0f64; 8]; 8];
    for k in 0..8 {
        for j in 0..8 {
            uu[k][j] = u[k * 8 + j];
        }
    }
    let main = n - n % 8;
    for s in (0..main).step_by(8) {
        upper8_rows::<8>(x, &uu, s);
    }
    // The last n mod 8 rows, one at a time.
    for s in main..n {
        upper8_rows::<1>(x, &uu, s);
    }
}

/// Rows s..s + W of [`mul_upper8`].
#[inline(always)]
fn upper8_rows<const W: usize>(x: &mut [&mut [f64]], uu: &[[f64; 8]; 8], s: usize) {
    let mut xs = [[0.0f64; W]; 8];
    for k in 0..8 {
        xs[k].copy_from_slice(&x[k][s..s + W]);
    }
    for j in 0..8 {
        let mut t = [0.0f64; W];
        for l in 0..W {
            t[l] = uu[j][j] * xs[j][l];
        }
        for k in 0..j {
            for l in 0..W {
                t[l] += uu[k][j] * xs[k][l];
            }
        }
        x[j][s..s + W].copy_from_slice(&t);
    }
}

macro_rules! build {
    ($name:ident, $feature:literal) => {
        #[cfg(target_arch = "x86_64")]
        pub mod $name {
            #[target_feature(enable = $feature)]
            pub fn spmm_rows(
                col_ptr: &[usize],
                row_idx: &[usize],
                val: &[f64],
                x: &[[f64; 8]],
                y: &mut [[f64; 8]],
            ) {
                super::spmm_rows(col_ptr, row_idx, val, x, y)
            }

            #[target_feature(enable = $feature)]
            pub fn ldlt_sweeps(cp: &[usize], ri: &[usize], l: &[f64], x: &mut [[f64; 8]]) {
                super::ldlt_sweeps(cp, ri, l, x)
            }

            #[target_feature(enable = $feature)]
            pub fn gram_sym(x: &[&[f64]], y: &[&[f64]], g: &mut [f64]) {
                super::gram_sym(x, y, g)
            }

            #[target_feature(enable = $feature)]
            pub fn mul_upper(x: &mut [&mut [f64]], u: &[f64]) {
                super::mul_upper(x, u)
            }
        }
    };
}
build!(avx2, "avx2");
build!(avx512, "avx512f");

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_cols(p: usize, n: usize, seed: u64) -> Vec<Vec<f64>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..p)
            .map(|_| (0..n).map(|_| rng.random::<f64>() - 0.5).collect())
            .collect()
    }

    /// The dispatch's promise: every instruction-set build gives bitwise the same result as
    /// the plain one (no FMA contraction, the same order of sums).
    #[test]
    fn every_build_is_bitwise_the_plain_one() {
        let n = 300;
        let x = random_cols(8, n, 1);
        let y = random_cols(8, n, 2);
        let (xs, ys): (Vec<&[f64]>, Vec<&[f64]>) = (
            x.iter().map(|c| c.as_slice()).collect(),
            y.iter().map(|c| c.as_slice()).collect(),
        );
        let (mut g0, mut g1) = (vec![0.0; 64], vec![0.0; 64]);
        gram_sym(&xs, &ys, &mut g0);
        simd_dispatch!(gram_sym(&xs, &ys, &mut g1));
        assert_eq!(g0, g1);

        for p in [5, 8] {
            let u: Vec<f64> = (0..p * p)
                .map(|k| {
                    if k / p <= k % p {
                        1.0 / (1 + k) as f64
                    } else {
                        0.0
                    }
                })
                .collect();
            let (mut a, mut b) = (random_cols(p, n, 3), random_cols(p, n, 3));
            let mut ac: Vec<&mut [f64]> = a.iter_mut().map(|c| c.as_mut_slice()).collect();
            let mut bc: Vec<&mut [f64]> = b.iter_mut().map(|c| c.as_mut_slice()).collect();
            mul_upper(&mut ac, &u);
            simd_dispatch!(mul_upper(&mut bc, &u));
            assert_eq!(a, b, "p = {p}");
        }
    }

    /// X·U against the textbook sum, in the same order (U_jj·x_j first, then k = 0..j), so
    /// equal to the bit; both the 8-column and the general path.
    #[test]
    fn upper_triangular_product_is_the_textbook_sum() {
        for p in [3, 8] {
            let n = 21;
            let x0 = random_cols(p, n, 4);
            let u: Vec<f64> = (0..p * p)
                .map(|k| {
                    if k / p <= k % p {
                        (k as f64).sin()
                    } else {
                        0.0
                    }
                })
                .collect();
            let mut want = x0.clone();
            for j in 0..p {
                for i in 0..n {
                    let mut t = u[j * p + j] * x0[j][i];
                    for k in 0..j {
                        t += u[k * p + j] * x0[k][i];
                    }
                    want[j][i] = t;
                }
            }
            let mut x = x0.clone();
            let mut xc: Vec<&mut [f64]> = x.iter_mut().map(|c| c.as_mut_slice()).collect();
            mul_upper(&mut xc, &u);
            assert_eq!(x, want, "p = {p}");
        }
    }

    /// The Gram matrix against plain dot products: eight lane sums change the order, so
    /// agreement to round-off of Σ|x||y| (≤ 300 · 0.25), 1e-13 absolute; exactly symmetric.
    #[test]
    fn gram_matches_dot_products_and_is_symmetric() {
        let (p, n) = (6, 300);
        let x = random_cols(p, n, 6);
        let xs: Vec<&[f64]> = x.iter().map(|c| c.as_slice()).collect();
        let mut g = vec![0.0; p * p];
        gram_sym(&xs, &xs, &mut g);
        for a in 0..p {
            for b in 0..p {
                let dot: f64 = x[a].iter().zip(&x[b]).map(|(u, v)| u * v).sum();
                assert!((g[a * p + b] - dot).abs() < 1e-13);
                assert_eq!(g[a * p + b], g[b * p + a]);
            }
        }
    }

    /// The LDLᵀ sweeps on a 3 × 3 factor written by hand (D first in each column, then the
    /// sub-diagonal of L), against the solution computed on paper: L = [1; 0.5 1; 0 0.25 1],
    /// D = diag(2, 4, 8), x = L⁻ᵀ·D⁻¹·L⁻¹·b. All values dyadic, so exact.
    #[test]
    fn ldlt_sweeps_solve_a_hand_factor() {
        let cp = [0, 2, 4, 5];
        let ri = [0, 1, 1, 2, 2];
        let l = [2.0, 0.5, 4.0, 0.25, 8.0];
        // A = L·D·Lᵀ = [2 1 0; 1 4.5 1; 0 1 8.25]; b = A·[1, −2, 4] = [0, −4, 31].
        let mut x = [[0.0; 8]; 3];
        for (k, b) in [0.0, -4.0, 31.0].iter().enumerate() {
            x[k][0] = *b;
            x[k][7] = 2.0 * b;
        }
        ldlt_sweeps(&cp, &ri, &l, &mut x);
        assert_eq!([x[0][0], x[1][0], x[2][0]], [1.0, -2.0, 4.0]);
        assert_eq!([x[0][7], x[1][7], x[2][7]], [2.0, -4.0, 8.0]);
    }
}
