//! Mirror symmetry of a pencil (K, M): the eigen-problem splits into independent symmetry
//! classes, each a quarter (two mirrors) or a half (one) of the unknowns.
//!
//! A mirror acts on the unknowns as a signed permutation g (g·e_i = s_i·e_{p(i)}). When
//! g·K·gᵀ = K and g·M·gᵀ = M for commuting mirrors g₁, g₂, every eigenvector can be chosen
//! even or odd under each, and the 2^k classes of sign patterns are orthogonal invariant
//! subspaces. With Q_c an orthonormal basis of class c (each column the orbit of one unknown,
//! combined with the class's signs), K·φ = λ·M·φ is the direct sum of the smaller pencils
//! (Q_cᵀ·K·Q_c, Q_cᵀ·M·Q_c): the same eigenvalues, and by congruence the Sturm counts of the
//! classes add up to the whole pencil's. The solver's cost grows with (unknowns) × (modes), so
//! two mirrors cut it about fourfold.
//!
//! The mirrors are proposed from the geometry by the caller and proven here, entry by entry
//! ([`SignedPerm::preserves`]): a model that is only nearly symmetric is solved whole.

use super::csc::SymCsc;
use crate::fem::model::Triplets;

/// The largest difference accepted between an entry and its mirror image, relative to its
/// scale (see [`SignedPerm::preserves`]). Mirrored elements are assembled from mirrored
/// coordinates, and the prestress comes from a static solve, so the images differ by
/// round-off: up to 2.2e-14 of the scale on the 60-satellite stack. A difference below 1e-12
/// moves the eigenvalues by less than the solver's own tolerance (`RESIDUAL_TOL`, 1e-10);
/// anything larger is a model that is not symmetric, and is solved whole.
pub const SYMMETRY_TOL: f64 = 1e-12;

/// A signed permutation of the unknowns: g·e_i = sign[i]·e_{perm[i]}.
#[derive(Debug, Clone, PartialEq)]
pub struct SignedPerm {
    pub perm: Vec<usize>,
    pub sign: Vec<f64>,
}

impl SignedPerm {
    /// Whether g is an involution (a mirror applied twice is the identity).
    pub fn is_involution(&self) -> bool {
        (0..self.perm.len()).all(|i| {
            let j = self.perm[i];
            j < self.perm.len() && self.perm[j] == i && self.sign[j] * self.sign[i] == 1.0
        })
    }

    /// Whether g·h = h·g.
    pub fn commutes_with(&self, h: &SignedPerm) -> bool {
        (0..self.perm.len()).all(|i| {
            let gh = (self.perm[h.perm[i]], self.sign[h.perm[i]] * h.sign[i]);
            let hg = (h.perm[self.perm[i]], h.sign[self.perm[i]] * self.sign[i]);
            gh == hg
        })
    }

    /// Whether g·A·gᵀ = A to [`SYMMETRY_TOL`]: every stored entry a_ij equals
    /// s_i·s_j·a_{p(i)p(j)} (an entry not stored counts as zero) within the tolerance times
    /// the larger of the two and √|a_ii·a_jj|, the scale of the entry's row and column (an
    /// entry that should be zero holds round-off of that scale).
    pub fn preserves(&self, a: &SymCsc) -> bool {
        let diag: Vec<f64> = (0..a.n).map(|i| a.entry(i, i).abs()).collect();
        (0..a.n).all(|j| {
            let (pj, sj) = (self.perm[j], self.sign[j]);
            (a.col_ptr[j]..a.col_ptr[j + 1]).all(|q| {
                let (i, v) = (a.row_idx[q], a.val[q]);
                let image = a.entry(self.perm[i], pj) * self.sign[i] * sj;
                let scale = image.abs().max(v.abs()).max((diag[i] * diag[j]).sqrt());
                (image - v).abs() <= SYMMETRY_TOL * scale
            })
        })
    }
}

/// One symmetry class: an orthonormal basis Q_c of its invariant subspace, each column one
/// orbit of unknowns with entries ±1/√|orbit|.
#[derive(Debug, Clone)]
pub struct SymmetryClass {
    /// The class's sign under each mirror (+1 even, −1 odd).
    pub signs: Vec<f64>,
    pub columns: Vec<Vec<(usize, f64)>>,
    /// For each unknown, its column in this class and its coefficient there.
    col_of: Vec<Option<(usize, f64)>>,
}

/// The classes of a set of commuting mirrors, or `None` if they do not split the unknowns
/// into 2^k classes of a basis (which would be a bug in the proposed mirrors).
pub fn symmetry_classes(n: usize, mirrors: &[SignedPerm]) -> Option<Vec<SymmetryClass>> {
    let group = group_elements(mirrors);
    let mut classes: Vec<SymmetryClass> = (0..1usize << mirrors.len())
        .map(|c| SymmetryClass {
            signs: (0..mirrors.len())
                .map(|b| if c >> b & 1 == 1 { -1.0 } else { 1.0 })
                .collect(),
            columns: Vec::new(),
            col_of: vec![None; n],
        })
        .collect();
    let mut seen = vec![false; n];
    for i in 0..n {
        if seen[i] {
            continue;
        }
        for (g, _) in &group {
            seen[g.perm[i]] = true;
        }
        for class in &mut classes {
            class.add_orbit_column(i, &group);
        }
    }
    let dims: usize = classes.iter().map(|c| c.columns.len()).sum();
    (dims == n).then_some(classes)
}

/// Every element of the group the commuting mirrors generate, with the mirrors it is made of
/// (bit b set: mirror b applied).
fn group_elements(mirrors: &[SignedPerm]) -> Vec<(SignedPerm, usize)> {
    let n = mirrors.first().map_or(0, |g| g.perm.len());
    let identity = SignedPerm {
        perm: (0..n).collect(),
        sign: vec![1.0; n],
    };
    let mut group = vec![(identity, 0usize)];
    for (b, g) in mirrors.iter().enumerate() {
        let more: Vec<(SignedPerm, usize)> = group
            .iter()
            .map(|(h, bits)| (compose(g, h), bits | 1 << b))
            .collect();
        group.extend(more);
    }
    group
}

/// g·h.
fn compose(g: &SignedPerm, h: &SignedPerm) -> SignedPerm {
    let n = h.perm.len();
    SignedPerm {
        perm: (0..n).map(|i| g.perm[h.perm[i]]).collect(),
        sign: (0..n).map(|i| g.sign[h.perm[i]] * h.sign[i]).collect(),
    }
}

impl SymmetryClass {
    /// The projection of e_i on this class, Σ_g χ(g)·g·e_i, as a new column if it is not zero.
    fn add_orbit_column(&mut self, i: usize, group: &[(SignedPerm, usize)]) {
        let mut entries: Vec<(usize, f64)> = Vec::new();
        for (g, bits) in group {
            let chi: f64 = (0..self.signs.len())
                .filter(|b| bits >> b & 1 == 1)
                .map(|b| self.signs[b])
                .product();
            let (j, v) = (g.perm[i], chi * g.sign[i]);
            match entries.iter_mut().find(|e| e.0 == j) {
                Some(e) => e.1 += v,
                None => entries.push((j, v)),
            }
        }
        entries.retain(|e| e.1 != 0.0);
        if entries.is_empty() {
            return;
        }
        entries.sort_by_key(|e| e.0);
        let norm = entries.iter().map(|e| e.1 * e.1).sum::<f64>().sqrt();
        let col = self.columns.len();
        for e in &mut entries {
            e.1 /= norm;
            self.col_of[e.0] = Some((col, e.1));
        }
        self.columns.push(entries);
    }

    /// Q_cᵀ·A·Q_c.
    pub fn project(&self, a: &SymCsc) -> SymCsc {
        let mut t: Triplets = Vec::with_capacity(a.val.len());
        for j in 0..a.n {
            let Some((cj, qj)) = self.col_of[j] else {
                continue;
            };
            for q in a.col_ptr[j]..a.col_ptr[j + 1] {
                if let Some((ci, qi)) = self.col_of[a.row_idx[q]] {
                    t.push((ci, cj, qi * a.val[q] * qj));
                }
            }
        }
        SymCsc::from_triplets(self.columns.len(), &t)
    }

    /// Q_c·x: a vector of the class in the whole model's unknowns.
    pub fn expand(&self, x: &[f64]) -> Vec<f64> {
        self.col_of
            .iter()
            .map(|c| c.map_or(0.0, |(col, q)| q * x[col]))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::RESIDUAL_TOL;
    use super::super::eigen::eigen;
    use super::super::testing::{chain, chain_eigenvalues, identity};
    use super::*;

    /// The chain reversed end to end: unknown i ↔ n−1−i, signs +1 (the chain is symmetric
    /// about its middle).
    fn reversal(n: usize) -> SignedPerm {
        SignedPerm {
            perm: (0..n).rev().collect(),
            sign: vec![1.0; n],
        }
    }

    /// The frequency (Hz) halfway between the chain's eigenvalues `j − 1` and `j`: a band
    /// edge in a gap, as the solver is used on a class (a band, not the lowest N).
    fn fmax_below(n: usize, k: f64, j: usize) -> f64 {
        let e = chain_eigenvalues(n, k);
        (0.5 * (e[j - 1] + e[j])).sqrt() / (2.0 * std::f64::consts::PI)
    }

    #[test]
    fn a_reversed_chain_splits_into_its_even_and_odd_modes() {
        // Odd length: the middle unknown is its own mirror image, in the even class only.
        let n = 161;
        let (k, m) = (chain(n, 3.0), identity(n));
        let g = reversal(n);
        assert!(g.is_involution() && g.preserves(&k) && g.preserves(&m));
        let classes = symmetry_classes(n, std::slice::from_ref(&g)).expect("a basis");
        assert_eq!(classes[0].columns.len(), 81);
        assert_eq!(classes[1].columns.len(), 80);
        // The union of the classes' spectra below the band edge is the chain's (analytic,
        // Dirichlet Laplacian), to the solver's first-order bound RESIDUAL_TOL·λ_top.
        let fmax = fmax_below(n, 3.0, 40);
        let mut lambdas: Vec<f64> = classes
            .iter()
            .flat_map(|c| {
                let (pairs, _) = eigen(&c.project(&k), &c.project(&m), Some(fmax), None).unwrap();
                pairs.into_iter().map(|p| p.0).collect::<Vec<_>>()
            })
            .collect();
        lambdas.sort_by(f64::total_cmp);
        let exact = chain_eigenvalues(n, 3.0);
        assert_eq!(lambdas.len(), 40);
        for (a, b) in lambdas.iter().zip(&exact) {
            assert!((a - b).abs() <= RESIDUAL_TOL * exact[40], "{a} against {b}");
        }
    }

    #[test]
    fn an_expanded_class_vector_is_an_eigenvector_of_the_whole_pencil() {
        // The chain's eigenvectors are sin(jπ(i+1)/(n+1)) (Dirichlet Laplacian); those with an
        // even j are odd under the reversal, and the lowest of them is j = 2.
        let n = 160;
        let (k, m) = (chain(n, 2.0), identity(n));
        let classes = symmetry_classes(n, &[reversal(n)]).unwrap();
        let odd = &classes[1];
        let fmax = fmax_below(n, 2.0, 10);
        let (pairs, _) = eigen(&odd.project(&k), &odd.project(&m), Some(fmax), None).unwrap();
        assert_eq!(pairs.len(), 5, "j = 2, 4, 6, 8, 10");
        let lambda = chain_eigenvalues(n, 2.0)[1];
        assert!((pairs[0].0 - lambda).abs() <= 1e-12 * lambda);
        let phi = odd.expand(&pairs[0].1);
        let exact: Vec<f64> = (0..n)
            .map(|i| (2.0 * std::f64::consts::PI * (i + 1) as f64 / (n + 1) as f64).sin())
            .collect();
        let norm = exact.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cos = phi.iter().zip(&exact).map(|(a, b)| a * b).sum::<f64>() / norm;
        // Unit M-norm (M = I) and parallel to the exact vector: 1 − |cos| is half the squared
        // angle, the solver's vector tolerance (VECTOR_TOL = 1e-9) squared or better.
        assert!((1.0 - cos.abs()).abs() < 1e-12, "cos {cos}");
    }

    #[test]
    fn a_perturbed_entry_breaks_the_symmetry() {
        let n = 6;
        let mut t: Triplets = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0));
        }
        t.push((0, 0, 1e-9));
        let k = SymCsc::from_triplets(n, &t);
        assert!(!reversal(n).preserves(&k));
    }

    #[test]
    fn mirrors_that_do_not_commute_are_told() {
        // Two different reversals of parts of a 3-cycle do not commute.
        let a = SignedPerm {
            perm: vec![1, 0, 2],
            sign: vec![1.0; 3],
        };
        let b = SignedPerm {
            perm: vec![0, 2, 1],
            sign: vec![1.0; 3],
        };
        assert!(a.is_involution() && b.is_involution());
        assert!(!a.commutes_with(&b));
    }
}
