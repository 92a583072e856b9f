//! The sparse eigen-solve: the Sturm count at the top of the band, a shift below the whole
//! spectrum, the bands run in parallel, each band's pairs cleaned up (Rayleigh quotients) and
//! handed to the caller on the band's thread as soon as it is solved.

use super::bands::{BAND_MODES, band_edges, run_band};
use super::csc::SymCsc;
use super::factor::{Pencil, factor_away_from_eigenvalue, point_in_gap};
use super::{Pair, SparseError};
use crate::error::ModalError;
use faer::{Mat, Par};

/// A shift and its Sturm count.
pub(super) type Edge = (f64, usize);

/// What the sparse eigen-solve did, for reports and benchmarks.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SparseStats {
    /// Shift (rad²/s²) and negative-pivot count of the final Sturm check.
    pub sturm_sigma: f64,
    pub sturm_count: usize,
    /// The count at (2π·fmax)², when `fmax_hz` was given.
    pub fmax_count: Option<usize>,
    pub factorizations: usize,
    /// Bands of the spectrum solved independently (in parallel), and clusters of repeated
    /// eigenvalues taken whole by subspace iteration.
    pub bands: usize,
    pub clusters: usize,
    pub slices: usize,
    pub lanczos_vectors: usize,
    pub restarts: usize,
    /// Largest ‖Kφ − λMφ‖₂ / ((‖K‖₁ + |λ|·‖M‖₁)·‖φ‖₂) over the returned modes.
    pub max_backward_error: f64,
    /// Values of the factor L, per factorization.
    pub factor_nnz: usize,
    /// Largest ratio of a diagonal entry of K − σM to its pivot, σ below the spectrum (as the
    /// dense path's `max_ratio`, one pivot per rigid-body mode discounted) and where it is.
    pub max_ratio: f64,
    pub max_ratio_at: String,
    /// The mirror planes and symmetry classes the solve was split into, when the model has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetry: Option<String>,
    /// A_ii / d_i of the factor below the spectrum, per reduced DOF (input order).
    #[serde(skip)]
    pub pivot_ratio: Vec<f64>,
}

/// The completeness proof: `expected` modes lie below `fmax_hz` by the Sturm count, `found`
/// were returned. Anything but equality is an error.
pub fn sturm_check(expected: usize, found: usize, fmax_hz: f64) -> Result<(), ModalError> {
    if expected == found {
        Ok(())
    } else {
        Err(ModalError::SturmMismatch {
            expected,
            found,
            fmax_hz,
        })
    }
}

/// Eigenpairs (λ ascending, φ mass-normalised) of K·φ = λ·M·φ: every mode below
/// (2π·fmax_hz)² and/or the lowest `modes`, proven complete by a Sturm count.
pub fn eigen(
    k: &SymCsc,
    m: &SymCsc,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
) -> Result<(Vec<Pair>, SparseStats), SparseError> {
    let keep_pairs = |band: FinishedBand, _: &mut SparseStats| Ok(band.pairs);
    let (bands, stats) = eigen_by_band(k, m, fmax_hz, modes, &keep_pairs)?;
    Ok((bands.into_iter().flatten().collect(), stats))
}

/// One band's eigenpairs once solved and cleaned up (Rayleigh quotients, λ ascending,
/// φ mass-normalised): the modes `offset..offset + pairs.len()` of the whole result.
pub struct FinishedBand {
    pub offset: usize,
    pub pairs: Vec<Pair>,
}

/// What a caller does with each band as soon as it is solved, on the band's own thread (the
/// band's statistics passed along for any further factorizations).
pub type BandFinish<'a, T> =
    dyn Fn(FinishedBand, &mut SparseStats) -> Result<T, SparseError> + Sync + 'a;

/// As [`eigen`], but each band's pairs go to `finish` on the band's thread as soon as the
/// band is solved, and its results come back in mode order. A caller that reduces the
/// pairs there (checks, effective masses) never holds every eigenvector at once, and that
/// work overlaps the other bands' solves. The results are those of [`eigen`] followed by
/// `finish` on consecutive runs of modes: the bands' ranges of λ do not overlap.
pub fn eigen_by_band<T: Send>(
    k: &SymCsc,
    m: &SymCsc,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
    finish: &BandFinish<'_, T>,
) -> Result<(Vec<T>, SparseStats), SparseError> {
    // The operator forms of faer products (`A * B`) follow the global setting: sequential,
    // as in the dense path, for thread-count-independent results.
    faer::set_global_parallelism(Par::Seq);
    let n = k.n;
    let two_pi = 2.0 * std::f64::consts::PI;
    let pencil = Pencil::new(k, Some(m))?;
    let mut stats = SparseStats {
        factor_nnz: pencil.factor_len(),
        ..Default::default()
    };
    let want_modes = modes.map(|x| x.min(n));
    if want_modes == Some(0) {
        return Ok((Vec::new(), stats));
    }
    // Sturm count at the top of the band, in a gap of the spectrum: a cluster of repeated
    // modes within EDGE_GAP of (2π·fmax)² is taken whole, the top moved just above it.
    let mut top: Option<Edge> = None;
    if let Some(f) = fmax_hz {
        let lmax = (two_pi * f).powi(2);
        let (sigma, count) = point_in_gap(&pencil, lmax, &mut stats)?;
        stats.fmax_count = Some(count);
        top = Some((sigma, count));
    }
    let target = match (top, want_modes) {
        (Some(t), Some(w)) => t.1.min(w),
        (Some(t), None) => t.1,
        (None, Some(w)) => w,
        (None, None) => {
            return Err(ModalError::Invalid(
                "the sparse solver needs [modal] fmax_hz or modes".into(),
            )
            .into());
        }
    };
    if target == 0 {
        let t = top.expect("target 0 without fmax means modes = 0, handled above");
        stats.sturm_sigma = t.0;
        stats.sturm_count = 0;
        return Ok((Vec::new(), stats));
    }
    // The counted top of the band: what no returned eigenvalue may reach.
    let lmax = fmax_hz.map(|f| top.map(|t| t.0).unwrap_or((two_pi * f).powi(2)));
    let low_sigma = shift_below_spectrum(&pencil, top.map(|t| t.0), &mut stats)?;
    let bands = spectrum_bands(&pencil, low_sigma, top, want_modes, &mut stats)?;
    let solved = solve_bands(m, &pencil, &bands, target, (k, lmax, finish));
    let mut outs = Vec::with_capacity(solved.len());
    for r in solved {
        let out = r?;
        stats.add_band(&out.stats);
        outs.push(out);
    }
    // Each slice matched its own count; the whole band is checked once more here (when
    // `modes` cut it short, the slices' counts up to the last edge are the proof).
    if let (Some(f), Some(count)) = (fmax_hz, stats.fmax_count)
        && target == count
    {
        sturm_check(count, outs.iter().map(|o| o.raw_below_top).sum(), f)?;
    }
    check_band_order(&outs)?;
    let kept: usize = outs.iter().map(|o| o.lambdas.len()).sum();
    stats.max_backward_error = outs
        .iter()
        .map(|o| o.max_backward_error)
        .fold(0.0, f64::max);
    if let (Some(f), Some(count), Some(l)) = (fmax_hz, stats.fmax_count, lmax)
        && kept == count
    {
        // The quotients moved by round-off only; none may cross the counted top.
        let below = outs
            .iter()
            .flat_map(|o| &o.lambdas)
            .filter(|&&x| x < l)
            .count();
        sturm_check(count, below, f)?;
    }
    let results = outs
        .into_iter()
        .map(|o| o.finished)
        .collect::<Result<_, _>>()?;
    Ok((results, stats))
}

/// One band, solved and finished on its thread.
struct BandOut<T> {
    /// Its eigenvalues below the counted top before the clean-up (the completeness proof).
    raw_below_top: usize,
    /// Index of its first mode in the whole result.
    offset: usize,
    /// Its kept eigenvalues after the Rayleigh quotients, ascending.
    lambdas: Vec<f64>,
    max_backward_error: f64,
    stats: SparseStats,
    finished: Result<T, SparseError>,
}

/// The bands' modes must follow each other: each band starts where the previous one ended,
/// and its eigenvalues lie above the previous band's (cuts sit in gaps of the spectrum far
/// wider than the round-off the Rayleigh quotients move them by).
fn check_band_order<T>(outs: &[BandOut<T>]) -> Result<(), SparseError> {
    let mut next = 0;
    let mut last = f64::NEG_INFINITY;
    for o in outs {
        let first = o.lambdas.first().copied().unwrap_or(f64::INFINITY);
        if o.offset != next || first < last {
            return Err(ModalError::NoConvergence(format!(
                "the spectrum's bands do not join: a band starting at mode {} follows {next} modes, its lowest eigenvalue {first:e} rad²/s² against {last:e} below it",
                o.offset + 1
            ))
            .into());
        }
        next += o.lambdas.len();
        last = o.lambdas.last().copied().unwrap_or(last);
    }
    Ok(())
}

impl SparseStats {
    /// Adds another solve's work: factorizations, clusters, slices, Lanczos vectors, restarts.
    pub fn add_work(&mut self, st: &SparseStats) {
        self.factorizations += st.factorizations;
        self.clusters += st.clusters;
        self.slices += st.slices;
        self.lanczos_vectors += st.lanczos_vectors;
        self.restarts += st.restarts;
    }

    /// Adds the work of one band; the Sturm check reported is the highest band's.
    fn add_band(&mut self, st: &SparseStats) {
        self.add_work(st);
        self.bands += 1;
        if st.sturm_count >= self.sturm_count {
            self.sturm_sigma = st.sturm_sigma;
            self.sturm_count = st.sturm_count;
        }
    }
}

/// A shift below the whole spectrum: a small fraction of a typical K_ii/M_ii (the Rayleigh
/// quotient of a unit vector, so of the order of the spectrum), pushed down until the count
/// is 0 (negative eigenvalues exist when the prestress exceeds the buckling load).
fn shift_below_spectrum(
    pencil: &Pencil,
    top_sigma: Option<f64>,
    stats: &mut SparseStats,
) -> Result<f64, SparseError> {
    let n = pencil.n;
    let dk = &pencil.diag_k;
    let dm = &pencil.diag_m;
    let mut ratios: Vec<f64> = (0..n)
        .filter(|&i| dk[i] > 0.0 && dm[i] > 0.0)
        .map(|i| dk[i] / dm[i])
        .collect();
    ratios.sort_by(f64::total_cmp);
    let mut s = ratios.get(ratios.len() / 2).copied().unwrap_or(1.0);
    if let Some(t) = top_sigma {
        s = s.min(t);
    }
    s *= 1e-6;
    for _ in 0..12 {
        // A band's top far below the spectrum's scale (fmax = 0.01 Hz on a free beam) puts
        // the shift inside the round-off of the rigid-body modes' zero: singular, so further
        // down, as for a count above 0.
        let fac = match factor_away_from_eigenvalue(pencil, -s, stats) {
            Err(SparseError::SingularNear { .. }) => {
                s *= 100.0;
                continue;
            }
            other => other?,
        };
        if fac.negative == 0 {
            stats.pivot_ratio = fac.pivot_ratios();
            return Ok(fac.sigma);
        }
        s *= 100.0;
    }
    Err(ModalError::NoConvergence(format!(
        "no shift below the spectrum found down to σ = {:e} rad²/s²",
        -s
    ))
    .into())
}

/// Bands of the spectrum, each solved independently (its own slices, locked vectors and
/// seed) and in parallel: (bottom edge, upper edge) pairs, the last one up to the counted top
/// (or open). The cut points depend only on the model, never on the number of threads, so
/// the result is the same on any machine.
fn spectrum_bands(
    pencil: &Pencil,
    low_sigma: f64,
    top: Option<Edge>,
    want_modes: Option<usize>,
    stats: &mut SparseStats,
) -> Result<Vec<(Edge, Option<Edge>)>, SparseError> {
    let edges = match top {
        Some((ts, tc)) if want_modes.is_none_or(|w| w >= tc) && tc >= 2 * BAND_MODES => {
            band_edges(pencil, (low_sigma, 0), (ts, tc), stats)?
        }
        _ => vec![(low_sigma, 0)],
    };
    let mut bands: Vec<(Edge, Option<Edge>)> =
        edges.windows(2).map(|w| (w[0], Some(w[1]))).collect();
    bands.push((*edges.last().expect("at least the bottom edge"), top));
    Ok(bands)
}

type BandResult<T> = Result<BandOut<T>, SparseError>;

/// A band's pairs (modes `offset..` of the whole) sorted, cut to the `target` modes, turned
/// into Rayleigh quotients and sorted again. Returns how many lay below the counted top
/// `lmax` before (the completeness proof) and the largest backward error. The bands' ranges
/// follow each other, so sorting and cutting each one is sorting and cutting the whole.
fn clean_up_band(
    mut pairs: Vec<Pair>,
    offset: usize,
    target: usize,
    (k, m, lmax): (&SymCsc, &SymCsc, Option<f64>),
) -> (usize, f64, FinishedBand) {
    let raw_below_top = lmax.map_or(0, |l| pairs.iter().filter(|p| p.0 < l).count());
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs.truncate(target.saturating_sub(offset));
    let max_backward_error = rayleigh_quotients(k, m, &mut pairs);
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    (
        raw_below_top,
        max_backward_error,
        FinishedBand { offset, pairs },
    )
}

/// Runs every band, on as many threads as rayon has, each cleaned up (Rayleigh quotients,
/// kept modes) and finished on its thread; returns the results in band order.
fn solve_bands<T: Send>(
    m: &SymCsc,
    pencil: &Pencil,
    bands: &[(Edge, Option<Edge>)],
    target: usize,
    (k, lmax, finish): (&SymCsc, Option<f64>, &BandFinish<'_, T>),
) -> Vec<BandResult<T>> {
    let run = |j: usize| -> BandResult<T> {
        let (bottom, upper) = bands[j];
        let mut stats = SparseStats::default();
        let t = upper.map(|u| u.1).unwrap_or(target).min(target);
        let pairs = run_band(
            m,
            pencil,
            bottom,
            upper,
            t,
            &mut stats,
            1 + 1_000_000 * j as u64,
        )?;
        let (raw_below_top, max_backward_error, band) =
            clean_up_band(pairs, bottom.1, target, (k, m, lmax));
        let (offset, lambdas) = (band.offset, band.pairs.iter().map(|p| p.0).collect());
        Ok(BandOut {
            raw_below_top,
            offset,
            lambdas,
            max_backward_error,
            finished: finish(band, &mut stats),
            stats,
        })
    };
    // Largest bands first from one shared queue, so that the band holding an unsplittable
    // cluster does not start last and leave the other threads idle. A band's result depends
    // only on its index (its edges and seed), never on which thread ran it or when.
    let mut order: Vec<usize> = (0..bands.len()).collect();
    let size = |j: usize| {
        bands[j]
            .1
            .map(|u| u.1)
            .unwrap_or(target)
            .saturating_sub(bands[j].0.1)
    };
    order.sort_by_key(|&j| (std::cmp::Reverse(size(j)), j));
    let slots: Vec<std::sync::Mutex<Option<BandResult<T>>>> =
        bands.iter().map(|_| std::sync::Mutex::new(None)).collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    rayon::scope(|sc| {
        for _ in 0..rayon::current_num_threads().min(bands.len()) {
            sc.spawn(|_| {
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(&j) = order.get(k) else { break };
                    let r = run(j);
                    *slots[j].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
                }
            });
        }
    });
    slots
        .into_iter()
        .map(|s| {
            s.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every band ran")
        })
        .collect()
}

/// Mass normalisation, the Rayleigh quotient and the true residuals; returns the largest
/// normwise backward error ‖Kφ − λMφ‖₂ / ((‖K‖₁ + |λ|·‖M‖₁)·‖φ‖₂).
///
/// Each eigenvalue is replaced by the Rayleigh quotient φᵀKφ / φᵀMφ of its vector. Its error
/// is second order in the vector's, whereas the Ritz value's is first order in a residual
/// that the projected problem estimates without the round-off of the operator: with the
/// rigid-body modes of a free-free model at θ = 1/|σ₀| that floor put elastic Ritz values
/// up to 1e-8 off the dense solver (tests/modal_sparse.rs); the quotient brings them to
/// round-off. K·φ and M·φ are computed here anyway.
fn rayleigh_quotients(k: &SymCsc, m: &SymCsc, accepted: &mut [Pair]) -> f64 {
    let n = k.n;
    let (nk, nm) = (k.norm1(), m.norm1());
    // In blocks of columns (matrix–block products without an n × modes copy of everything),
    // in parallel: the largest backward error does not depend on the order.
    use rayon::prelude::*;
    accepted
        .par_chunks_mut(64)
        .map(|chunk| {
            let mut worst = 0.0f64;
            let x = Mat::<f64>::from_fn(n, chunk.len(), |i, j| chunk[j].1[i]);
            let mx = m.mul(x.as_ref());
            let kx = k.mul(x.as_ref());
            for (j, (lambda, phi)) in chunk.iter_mut().enumerate() {
                let mass: f64 = (0..n).map(|i| phi[i] * mx[(i, j)]).sum();
                let stiff: f64 = (0..n).map(|i| phi[i] * kx[(i, j)]).sum();
                *lambda = stiff / mass;
                let scale = 1.0 / mass.sqrt();
                let mut r2 = 0.0;
                let mut p2 = 0.0;
                for i in 0..n {
                    let r = kx[(i, j)] - *lambda * mx[(i, j)];
                    r2 += r * r;
                    p2 += phi[i] * phi[i];
                    phi[i] *= scale;
                }
                let be = r2.sqrt() / ((nk + lambda.abs() * nm) * p2.sqrt());
                worst = worst.max(be);
            }
            worst
        })
        .reduce(|| 0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::super::RESIDUAL_TOL;
    use super::super::factor::EDGE_GAP;
    use super::super::testing::{chain, chain_eigenvalues, csc, diagonal, identity};
    use super::*;

    fn solve(n: usize, fmax_hz: f64) -> (Vec<Pair>, SparseStats) {
        eigen(&chain(n, 1.0), &identity(n), Some(fmax_hz), None).unwrap()
    }

    /// A 700-mass chain up to a frequency holding 320 modes (so more than one band): the
    /// count matches the analytic one and every eigenvalue is within the first-order
    /// acceptance bound RESIDUAL_TOL·λ_top of the analytic value; shapes mass-normalised
    /// (φᵀMφ = 1 to 1e-12, the Rayleigh-quotient step divides by the computed mass).
    #[test]
    fn spring_chain_spectrum_is_found_whole() {
        let n = 700;
        let exact = chain_eigenvalues(n, 1.0);
        let ltop = 0.5 * (exact[319] + exact[320]);
        let fmax = ltop.sqrt() / (2.0 * std::f64::consts::PI);
        let (pairs, stats) = solve(n, fmax);
        assert_eq!(stats.fmax_count, Some(320));
        assert_eq!(pairs.len(), 320);
        assert!(stats.bands > 1);
        for ((l, phi), want) in pairs.iter().zip(&exact) {
            assert!((l - want).abs() <= RESIDUAL_TOL * ltop, "{l} vs {want}");
            let mass: f64 = phi.iter().map(|x| x * x).sum();
            assert!((mass - 1.0).abs() < 1e-12);
        }
    }

    /// The bands' cuts and seeds depend on the model only: one thread and two give the same
    /// bits.
    #[test]
    fn result_does_not_depend_on_the_thread_count() {
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| solve(600, 0.25).0)
        };
        let (one, two) = (run(1), run(2));
        assert!(one.len() > 2 * BAND_MODES);
        for (a, b) in one.iter().zip(&two) {
            assert_eq!(a.0.to_bits(), b.0.to_bits());
            assert!(
                a.1.iter()
                    .zip(&b.1)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
            );
        }
        assert_eq!(one.len(), two.len());
    }

    /// 1, 2, …, 80 and 25 copies of 50.5 (M = I): the stack's column-joint cluster near the
    /// top of the band on a fine mesh.
    fn clustered_spectrum() -> Vec<f64> {
        let mut d: Vec<f64> = (1..=80).map(f64::from).collect();
        d.extend(std::iter::repeat_n(50.5, 25));
        d
    }

    fn solve_to(d: &[f64], lambda_top: f64) -> (Vec<Pair>, SparseStats) {
        let fmax = lambda_top.sqrt() / (2.0 * std::f64::consts::PI);
        eigen(&diagonal(d), &identity(d.len()), Some(fmax), None).unwrap()
    }

    fn copies_of(pairs: &[Pair], l: f64) -> usize {
        pairs
            .iter()
            .filter(|p| (p.0 - l).abs() <= RESIDUAL_TOL * l)
            .count()
    }

    /// A 25-fold eigenvalue just below the top of the band, above the last slice's shift: the
    /// slice whose run of converged values reaches the top must still bring in every copy.
    /// Below λ = 50.75 lie exactly 50 + 25 eigenvalues (the spectrum's definition).
    #[test]
    fn a_cluster_just_below_the_top_is_taken_whole() {
        let (pairs, stats) = solve_to(&clustered_spectrum(), 50.75);
        assert_eq!(stats.fmax_count, Some(75));
        assert_eq!(pairs.len(), 75);
        assert_eq!(copies_of(&pairs, 50.5), 25);
    }

    /// A band top exactly on the 25-fold eigenvalue, or exactly on a simple one: the top
    /// moves into the gap just above it (EDGE_GAP), so the cluster is taken whole and the
    /// count includes it: 50 + 25 below 50.5⁺, 51 + 25 below 51⁺.
    #[test]
    fn a_top_on_an_eigenvalue_keeps_it_whole() {
        let d = clustered_spectrum();
        let (pairs, stats) = solve_to(&d, 50.5);
        assert_eq!(stats.fmax_count, Some(75));
        assert_eq!(pairs.len(), 75);
        assert_eq!(copies_of(&pairs, 50.5), 25);
        let (pairs, stats) = solve_to(&d, 51.0);
        assert_eq!(stats.fmax_count, Some(76));
        assert_eq!(pairs.len(), 76);
        assert_eq!(copies_of(&pairs, 51.0), 1);
    }

    /// `copies` uncoupled n-mass chains (each eigenvalue of the chain `copies` times).
    fn chains(n: usize, copies: usize) -> (SymCsc, Vec<f64>) {
        let k = csc(n * copies, |i, j| {
            if i / n != j / n {
                return 0.0;
            }
            match i.abs_diff(j) {
                0 => 2.0,
                1 => -1.0,
                _ => 0.0,
            }
        });
        let mut exact: Vec<f64> = chain_eigenvalues(n, 1.0)
            .into_iter()
            .flat_map(|l| std::iter::repeat_n(l, copies))
            .collect();
        exact.sort_by(f64::total_cmp);
        (k, exact)
    }

    /// A request: the band's top frequency and/or the number of lowest modes.
    type Ask = (Option<f64>, Option<usize>);

    /// Solves (k, m) for every ask: as many modes as `exact` (ascending) holds below the top
    /// (raised by `top_factor`) and the count asked, each within `tol` of its exact value.
    fn assert_asks(
        k: &SymCsc,
        m: &SymCsc,
        exact: &[f64],
        asks: &[Ask],
        (top_factor, tol): (f64, f64),
        model: &str,
    ) {
        let two_pi = 2.0 * std::f64::consts::PI;
        for &(fmax, modes) in asks {
            let top = fmax.map(|f| (two_pi * f).powi(2) * top_factor);
            let below = exact.iter().filter(|&&l| top.is_none_or(|t| l < t));
            let want = below.count().min(modes.unwrap_or(usize::MAX));
            let case = format!("{model}, fmax {fmax:?}, modes {modes:?}");
            let (pairs, _) = eigen(k, m, fmax, modes).expect(&case);
            assert_eq!(pairs.len(), want, "{case}");
            for (p, l) in pairs.iter().zip(exact) {
                assert!((p.0 - l).abs() <= tol, "{case}: {} vs {l}", p.0);
            }
        }
    }

    /// Models smaller than a Lanczos basis, asked for a few modes, all of them, or a band:
    /// the count is the analytic one (a top on an eigenvalue takes it, EDGE_GAP) and every
    /// eigenvalue is within 1e-9 of λ_j = 4 sin²(jπ/(2(n+1))). Chains of 9–48 masses
    /// failed or came out wrong by 3.7e-3 before: one block of 8 per restart, and shifts on
    /// K_ii/M_ii = 2 where LDLᵀ without pivoting loses every digit.
    #[test]
    fn models_smaller_than_a_basis_are_solved_exactly() {
        let two_pi = 2.0 * std::f64::consts::PI;
        for copies in [1, 4] {
            for n in [1, 2, 5, 9, 12, 23, 41, 48, 50, 64] {
                let (k, exact) = chains(n, copies);
                let m = identity(n * copies);
                let mut asks: Vec<Ask> = [1, 3, 8, 24, 250].map(|w| (None, Some(w))).to_vec();
                for l in [0.05, 1.0, 2.0, 3.9, 10.0] {
                    asks.push((Some(f64::sqrt(l) / two_pi), None));
                    asks.push((Some(f64::sqrt(l) / two_pi), Some(3)));
                }
                let model = format!("{copies} × {n} masses");
                assert_asks(&k, &m, &exact, &asks, (1.0 + EDGE_GAP, 1e-9), &model);
            }
        }
    }

    /// Chains of unequal masses (1–3 kg), anchored or free at both ends (one rigid-body
    /// mode), asked for a few modes, all, bands holding 10%, 50% and 90% of the spectrum, or
    /// a band holding only the rigid-body mode: the count is the dense solver's and every
    /// eigenvalue is within 1e-9 of the spectrum's top of its dense value. The last put the
    /// shifts inside the round-off of the rigid mode's zero (a singular factor, an error)
    /// before the bottom shift and the first probe stepped clear of it.
    #[test]
    fn anchored_and_free_chains_of_unequal_masses_agree_with_the_dense_solver() {
        let two_pi = 2.0 * std::f64::consts::PI;
        for free in [false, true] {
            for n in [3, 17, 70, 201] {
                let end = |i: usize| free && (i == 0 || i == n - 1);
                let k = csc(n, |i, j| match i.abs_diff(j) {
                    0 if end(i) => 1.0,
                    0 => 2.0,
                    1 => -1.0,
                    _ => 0.0,
                });
                let masses: Vec<f64> = (0..n).map(|i| 1.0 + ((i * 7) % 5) as f64 / 2.0).collect();
                let m = diagonal(&masses);
                let (exact, _) = crate::modal::dense::generalized_whole_spectrum(
                    &super::super::testing::dense(&k),
                    &super::super::testing::dense(&m),
                )
                .unwrap();
                let scale = exact[n - 1];
                let mut asks: Vec<Ask> = [1, 8, 250].map(|w| (None, Some(w))).to_vec();
                for q in [0.1, 0.5, 0.9] {
                    let l = exact[((n as f64 * q) as usize).max(1)] * 1.0001;
                    asks.push((Some(l.max(0.0).sqrt() / two_pi), None));
                }
                // A top of 1e-6 rad²/s²: the rigid-body mode alone, or nothing.
                asks.push((Some(1e-6f64.sqrt() / two_pi), None));
                let model = format!("free {free}, {n} masses");
                assert_asks(&k, &m, &exact, &asks, (1.0, 1e-9 * scale), &model);
            }
        }
    }

    #[test]
    fn sturm_check_accepts_only_equality() {
        assert!(sturm_check(4, 4, 10.0).is_ok());
        assert_eq!(
            sturm_check(4, 3, 10.0),
            Err(ModalError::SturmMismatch {
                expected: 4,
                found: 3,
                fmax_hz: 10.0
            })
        );
    }
}
