//! What the dense eigen-solve proves about its own modes: each eigenpair's backward error,
//! which modes are rigid-body modes (λ zero to round-off), and the conditioning of the
//! factored stiffness (Nastran's MAXRATIO) with the node and springs it points at.

use crate::fem::model::{FeModel, Reduction, Triplets};
use serde::Serialize;

/// Backward error above which an eigenpair is reported as not solved to working precision.
/// A stable dense solve gives ~1e-15 (n·ε); 1e-8 leaves seven decades for the scale of the
/// model and flags a pair whose λ has lost half its digits.
pub const MAX_BACKWARD_ERROR: f64 = 1e-8;
/// MAXRATIO above which the stiffness is poorly conditioned: Nastran's default threshold
/// (parameter MAXRATIO = 1e7, MSC Nastran Quick Reference Guide).
pub const MAX_PIVOT_RATIO: f64 = 1e7;
/// A pivot ratio beyond which fewer digits are left than the zero-eigenvalue test needs
/// (1/(1000·ε) ≈ 4.5e12): the zero test can then no longer tell a flexible mode from a
/// rigid-body one.
pub const LOST_PIVOT_RATIO: f64 = 1.0 / (ZERO_EIGENVALUE_ULPS * f64::EPSILON);
/// A λ within this many round-off units ε·(|φ|ᵀ|K||φ| + |σ|) of zero is a zero eigenvalue:
/// the factorization of K − σM perturbs K by about ε·|K|, and λ = σ + 1/θ adds the rounding
/// of the shift (φ is mass-normalised, so |σ|·φᵀMφ = |σ|); a rigid-body mode's λ comes out at
/// that size with either sign.
const ZERO_EIGENVALUE_ULPS: f64 = 1e3;

/// How the dense solve went: the shift it factored, the conditioning of that factor, and the
/// worst backward error of the modes it returned.
#[derive(Debug, Clone, Serialize)]
pub struct DenseStats {
    /// σ of the factored K − σM, rad²/s².
    pub shift: f64,
    /// Largest ratio of a diagonal entry of K − σM to its pivot, one pivot per rigid-body
    /// mode discounted (those pivots are σ·m by construction).
    pub max_ratio: f64,
    /// The node and DOF of that pivot.
    pub max_ratio_at: String,
    /// Largest ‖Kφ − λMφ‖ / (‖|K||φ|‖ + |λ|·‖|M||φ|‖) over the returned modes.
    pub max_backward_error: f64,
}

/// One eigenpair's residual figures.
pub struct PairCheck {
    /// Normwise backward error of (λ, φ).
    pub backward_error: f64,
    /// Whether λ is zero to round-off.
    pub zero: bool,
}

/// A triplet matrix grouped by row, the duplicates of each entry summed (the assembly writes
/// one triplet per element and DOF pair, about ten per stored value on the stacks), each row's
/// entries by column: one check reads each row once and checks of many modes share it.
pub struct RowTriplets {
    start: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl RowTriplets {
    /// `a` (rows below `n`) grouped by row, duplicates summed in their triplet order.
    pub fn new(n: usize, a: &Triplets) -> RowTriplets {
        let mut count = vec![0usize; n + 1];
        for &(i, _, _) in a {
            count[i + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut next = count.clone();
        let mut grouped = vec![(0, 0.0); a.len()];
        for &(i, j, v) in a {
            grouped[next[i]] = (j, v);
            next[i] += 1;
        }
        let mut start = vec![0usize; n + 1];
        let mut entries: Vec<(usize, f64)> = Vec::with_capacity(a.len() / 4);
        for i in 0..n {
            let row = &mut grouped[count[i]..count[i + 1]];
            // Stable: equal columns keep their triplet order, so the sums are reproducible.
            row.sort_by_key(|e| e.0);
            for &(j, v) in row.iter() {
                let row_has = entries.len() > start[i];
                match entries.last_mut() {
                    Some(last) if row_has && last.0 == j => last.1 += v,
                    _ => entries.push((j, v)),
                }
            }
            start[i + 1] = entries.len();
        }
        RowTriplets { start, entries }
    }

    /// A·φ_b and |A|·|φ_b| for the `nb` modes of `phis`, interleaved (entry j of mode b at
    /// j·nb + b, and so the results): each row is read once for the block, and each mode's
    /// row sum runs over the entries in triplet order, as a check of that mode alone would.
    fn block_products(&self, phis: &[f64], nb: usize) -> (Vec<f64>, Vec<f64>) {
        let n = self.start.len() - 1;
        let mut y = vec![0.0; n * nb];
        let mut z = vec![0.0; n * nb];
        for (i, (yi, zi)) in y
            .chunks_exact_mut(nb)
            .zip(z.chunks_exact_mut(nb))
            .enumerate()
        {
            for &(j, v) in &self.entries[self.start[i]..self.start[i + 1]] {
                let pj = &phis[j * nb..(j + 1) * nb];
                for b in 0..nb {
                    yi[b] += v * pj[b];
                    zi[b] += v.abs() * pj[b].abs();
                }
            }
        }
        (y, z)
    }
}

/// The residual checks of a model's pairs, its K and M grouped by row once for all of them.
pub struct PairChecker {
    k: RowTriplets,
    m: RowTriplets,
}

impl PairChecker {
    pub fn new(n: usize, (k, m): (&Triplets, &Triplets)) -> PairChecker {
        PairChecker {
            k: RowTriplets::new(n, k),
            m: RowTriplets::new(n, m),
        }
    }

    /// Every pair's check, in parallel (each is independent of the others), in mode order.
    pub fn check(&self, shapes: &[(f64, Vec<f64>)], shift_abs: f64) -> Vec<PairCheck> {
        use rayon::prelude::*;
        shapes
            .par_chunks(CHECK_BLOCK)
            .flat_map_iter(|block| check_pairs_block(&self.k, &self.m, block, shift_abs))
            .collect()
    }
}

/// Modes checked together by [`check_pairs_block`]: K and M are read once per block.
pub const CHECK_BLOCK: usize = 8;

/// The backward error of each (λ, φ) of `pairs` (a block of a few) and whether λ is a
/// round-off zero, for λs computed with the shift σ (`shift_abs` = |σ|; 0 for λs computed
/// without one). Each figure is the same as the block of that pair alone gives.
pub fn check_pairs_block(
    k: &RowTriplets,
    m: &RowTriplets,
    pairs: &[(f64, Vec<f64>)],
    shift_abs: f64,
) -> Vec<PairCheck> {
    let nb = pairs.len();
    let Some(n) = pairs.first().map(|p| p.1.len()) else {
        return Vec::new();
    };
    let mut phis = vec![0.0; n * nb];
    for (b, (_, phi)) in pairs.iter().enumerate() {
        for (j, &v) in phi.iter().enumerate() {
            phis[j * nb + b] = v;
        }
    }
    let (kphi, kabs) = k.block_products(&phis, nb);
    let (mphi, mabs) = m.block_products(&phis, nb);
    let lambdas: Vec<f64> = pairs.iter().map(|p| p.0).collect();
    let sums = block_sums(&lambdas, &phis, [&kphi, &kabs, &mphi, &mabs]);
    (0..nb)
        .map(|b| {
            let [r2, kabs2, mabs2, energy_floor] = sums[b];
            let lambda = lambdas[b];
            let (r, scale) = (r2.sqrt(), kabs2.sqrt() + lambda.abs() * mabs2.sqrt());
            PairCheck {
                backward_error: if scale > 0.0 { r / scale } else { 0.0 },
                zero: lambda.abs()
                    <= ZERO_EIGENVALUE_ULPS * f64::EPSILON * (energy_floor + shift_abs),
            }
        })
        .collect()
}

/// For each mode b of the block (entries interleaved, i·nb + b): ‖Kφ − λMφ‖², ‖|K||φ|‖²,
/// ‖|M||φ|‖² and Σ|φ|·|K||φ|, in one pass over the rows (each mode's sums in row order).
fn block_sums(
    lambdas: &[f64],
    phis: &[f64],
    [kphi, kabs, mphi, mabs]: [&[f64]; 4],
) -> Vec<[f64; 4]> {
    let nb = lambdas.len();
    let mut sums = vec![[0.0f64; 4]; nb];
    for i in 0..phis.len() / nb {
        for (b, acc) in sums.iter_mut().enumerate() {
            let at = i * nb + b;
            let r = kphi[at] - lambdas[b] * mphi[at];
            acc[0] += r * r;
            acc[1] += kabs[at] * kabs[at];
            acc[2] += mabs[at] * mabs[at];
            acc[3] += phis[at].abs() * kabs[at];
        }
    }
    sums
}

/// The largest pivot ratio after discounting the `rigid` largest (one tiny pivot per
/// rigid-body mode), and its reduced DOF index.
pub fn max_ratio(pivot_ratio: &[f64], rigid: usize) -> (f64, usize) {
    let mut order: Vec<usize> = (0..pivot_ratio.len()).collect();
    // Descending, ties by index: deterministic whatever the sort's stability.
    order.sort_by(|&a, &b| pivot_ratio[b].total_cmp(&pivot_ratio[a]).then(a.cmp(&b)));
    match order.get(rigid) {
        Some(&i) => (pivot_ratio[i], i),
        None => (1.0, 0),
    }
}

/// The warning for a poorly conditioned stiffness: the node and DOF of the worst pivot and the
/// springs attached to that node, with the remedy.
pub fn conditioning_warning(model: &FeModel, red: &Reduction, ratio: f64, index: usize) -> String {
    let full = red.red_to_full[index];
    let (node, _, dof_name) = model.dof_label(full);
    let springs: Vec<&str> = model
        .springs
        .iter()
        .zip(&model.spring_names)
        .filter(|(s, _)| s.nodes.contains(&(full / 6)))
        .map(|(_, name)| name.as_str())
        .collect();
    let at = if springs.is_empty() {
        String::new()
    } else {
        format!(" (spring {})", springs.join(", "))
    };
    format!(
        "poorly conditioned stiffness: MAXRATIO {ratio:.3e} (> {MAX_PIVOT_RATIO:.0e}) at {node} {dof_name}{at}: a stiffness that many times its neighbours costs that many digits of the modes; model a rigid connection with [[rigid]] instead of a stiff spring"
    )
}

/// The DOF label of a reduced index, as `node 3 rz`.
pub fn dof_name(model: &FeModel, red: &Reduction, index: usize) -> String {
    let (node, _, dof_name) = model.dof_label(red.red_to_full[index]);
    format!("{node} {dof_name}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K = diag(2, 0), M = I: (2, e₁) and (0, e₂) are exact eigenpairs (backward error 0,
    /// the second a zero); (1, e₁) has residual 1 against the scale 2 + 1 = 3.
    #[test]
    fn exact_pairs_have_no_residual_and_a_zero_is_recognised() {
        let k = RowTriplets::new(2, &vec![(0, 0, 2.0)]);
        let m = RowTriplets::new(2, &vec![(0, 0, 1.0), (1, 1, 1.0)]);
        let pairs = [
            (2.0, vec![1.0, 0.0]),
            (0.0, vec![0.0, 1.0]),
            (1.0, vec![1.0, 0.0]),
        ];
        let checks = check_pairs_block(&k, &m, &pairs, 0.0);
        let [c, z, off] = &checks[..] else {
            panic!("one check per pair");
        };
        assert_eq!(c.backward_error, 0.0);
        assert!(!c.zero);
        assert!(z.zero);
        assert!((off.backward_error - 1.0 / 3.0).abs() < 1e-15);
    }

    /// Ratios [5, 1e9, 3]: with one rigid-body pivot discounted the max is 5 at index 0.
    #[test]
    fn max_ratio_discounts_one_pivot_per_rigid_body_mode() {
        assert_eq!(max_ratio(&[5.0, 1e9, 3.0], 0), (1e9, 1));
        assert_eq!(max_ratio(&[5.0, 1e9, 3.0], 1), (5.0, 0));
    }
}
