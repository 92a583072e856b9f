//! The sparse eigen-solve of a mirror-symmetric model, one symmetry class at a time
//! ([`super::mirrors`]): each class's pencil is solved by the same sparse solver with its own
//! Sturm proof, its modes expanded to the whole model's DOFs and checked there, and the
//! classes' modes merged in frequency order.

use super::mirrors::Mirrors;
use super::sparse::symmetry::SymmetryClass;
use super::sparse::{self, FinishedBand, SparseError, SparseStats, SymCsc};
use super::{ModalOptions, Mode, ModeBasis, checks, polish_unconverged, set_zero_modes};
use crate::fem::model::Triplets;
use rayon::prelude::*;

/// One class's checked modes and the statistics of its solve.
type ClassModes = (Vec<(checks::PairCheck, Mode)>, SparseStats);

/// Every mode below `opts.fmax_hz` of the model whose mirrors are `mirrors`: the checked
/// pairs and modes in frequency order (indices renumbered), and the classes' statistics
/// added up (their Sturm counts sum to the whole model's, by congruence).
pub(super) fn solve_by_class(
    mirrors: &Mirrors,
    (k, m): (&Triplets, &Triplets),
    (kc, mc): (&SymCsc, &SymCsc),
    basis: &ModeBasis,
    opts: &ModalOptions,
) -> Result<(Vec<checks::PairCheck>, Vec<Mode>, SparseStats), SparseError> {
    let checker = checks::PairChecker::new(kc.n, (k, m));
    let solved: Vec<Result<ClassModes, SparseError>> = mirrors
        .classes
        .par_iter()
        .map(|class| solve_class(class, &checker, (kc, mc), basis, opts))
        .collect();
    let mut all: Vec<(checks::PairCheck, Mode)> = Vec::new();
    let mut stats: Vec<SparseStats> = Vec::new();
    for r in solved {
        let (modes, st) = r?;
        all.extend(modes);
        stats.push(st);
    }
    // Stable: equal frequencies keep the class order, so the result is deterministic.
    all.sort_by(|a, b| a.1.eigenvalue.total_cmp(&b.1.eigenvalue));
    let (checked, mut modes): (Vec<_>, Vec<_>) = all.into_iter().unzip();
    for (i, md) in modes.iter_mut().enumerate() {
        md.index = i + 1;
    }
    let mut total = add_up(&stats, mirrors);
    total.pivot_ratio = pivot_ratios(&mirrors.classes, &stats, kc.n);
    Ok((checked, modes, total))
}

/// One class: its projected pencil solved, each band's pairs expanded to the whole model and
/// checked, polished and measured there.
fn solve_class(
    class: &SymmetryClass,
    checker: &checks::PairChecker,
    (kc, mc): (&SymCsc, &SymCsc),
    basis: &ModeBasis,
    opts: &ModalOptions,
) -> Result<ClassModes, SparseError> {
    let (k_class, m_class) = (class.project(kc), class.project(mc));
    let finish = |band: FinishedBand, st: &mut SparseStats| {
        let mut pairs: Vec<(f64, Vec<f64>)> = band
            .pairs
            .into_iter()
            .map(|(lambda, x)| (lambda, class.expand(&x)))
            .collect();
        let mut checked = checker.check(&pairs, 0.0);
        polish_unconverged(checker, (kc, mc), &mut pairs, &mut checked, st)?;
        set_zero_modes(&checked, &mut pairs);
        let modes = basis.modes(pairs, band.offset, opts.shapes);
        Ok(checked.into_iter().zip(modes).collect::<Vec<_>>())
    };
    let (bands, stats) = sparse::eigen_by_band(&k_class, &m_class, opts.fmax_hz, None, &finish)?;
    Ok((bands.into_iter().flatten().collect(), stats))
}

/// The classes' statistics as one solve's: work and counts added, the lowest of the counted
/// tops (each class proved its own count below its own top, all at or above fmax), the
/// largest backward error.
fn add_up(stats: &[SparseStats], mirrors: &Mirrors) -> SparseStats {
    let mut t = SparseStats {
        sturm_sigma: f64::INFINITY,
        ..Default::default()
    };
    for s in stats {
        t.sturm_sigma = t.sturm_sigma.min(s.sturm_sigma);
        t.sturm_count += s.sturm_count;
        t.fmax_count = Some(t.fmax_count.unwrap_or(0) + s.fmax_count.unwrap_or(0));
        t.add_work(s);
        t.bands += s.bands;
        t.max_backward_error = t.max_backward_error.max(s.max_backward_error);
        t.factor_nnz += s.factor_nnz;
    }
    let sum = |terms: Vec<usize>| {
        let terms: Vec<String> = terms.iter().map(usize::to_string).collect();
        terms.join(" + ")
    };
    t.symmetry = Some(format!(
        "mirror planes {}: {} classes of {} DOFs, {} modes",
        mirrors.planes.join(", "),
        mirrors.classes.len(),
        sum(mirrors.classes.iter().map(|c| c.columns.len()).collect()),
        sum(stats.iter().map(|s| s.sturm_count).collect()),
    ));
    t
}

/// The classes' pivot ratios (A_ii / d_i below the spectrum) on the whole model's DOFs: a
/// class's column stands for one orbit of mirror-image DOFs, and the orbit's classes take its
/// DOFs in turn, so that each ratio is counted once.
fn pivot_ratios(classes: &[SymmetryClass], stats: &[SparseStats], n: usize) -> Vec<f64> {
    let mut ratio = vec![1.0; n];
    let mut taken = vec![0usize; n];
    for (class, st) in classes.iter().zip(stats) {
        for (col, entries) in class.columns.iter().enumerate() {
            let first = entries[0].0;
            let slot = entries[taken[first].min(entries.len() - 1)].0;
            taken[first] += 1;
            ratio[slot] = st.pivot_ratio.get(col).copied().unwrap_or(1.0);
        }
    }
    ratio
}
