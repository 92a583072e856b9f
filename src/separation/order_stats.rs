//! Distribution-free statistics of a Monte Carlo sample: what n runs can say about a
//! probability bound, from the order statistics alone (Wilks 1941; Conover, *Practical
//! Nonparametric Statistics*, 3rd ed., §3.2 and §3.3).
//!
//! For n independent samples of a continuous quantity X with quantile ξ_q (P(X ≤ ξ_q) = q),
//! the number of samples at or below ξ_q is Binomial(n, q), whatever the distribution of X.
//! Hence:
//! - the r-th smallest sample X₍r₎ is a lower bound of the (1 − q)-content, i.e. of ξ_q, with
//!   confidence P(X₍r₎ ≤ ξ_q) = P(Binomial(n, q) ≥ r);
//! - [X₍l₎, X₍u₎) covers ξ_q with probability F(u − 1) − F(l − 1), F the Binomial(n, q) CDF.
//!
//! With zero exceedances (r = 1, the extreme sample) the confidence is 1 − p^n for a p-bound,
//! so the runs needed are the smallest n with 1 − p^n ≥ C: n = ⌈ln(1 − C)/ln p⌉.

/// The smallest number of runs whose extreme sample bounds the `probability` quantile with at
/// least `confidence`: the smallest n with 1 − pⁿ ≥ C. `None` for arguments outside (0, 1).
pub fn runs_needed(probability: f64, confidence: f64) -> Option<usize> {
    if !(in_open_unit(probability) && in_open_unit(confidence)) {
        return None;
    }
    let estimate = ((1.0 - confidence).ln() / probability.ln()).ceil().max(1.0) as usize;
    // The closed form is exact up to the rounding of the logarithms; settle the integer on
    // the defining inequality itself.
    let enough = |n: usize| 1.0 - probability.powf(n as f64) >= confidence;
    let mut n = estimate;
    while n > 1 && enough(n - 1) {
        n -= 1;
    }
    while !enough(n) {
        n += 1;
    }
    Some(n)
}

/// The largest probability whose bound `runs` samples demonstrate at `confidence` with their
/// extreme sample: p = (1 − C)^(1/n). 0 for no runs.
pub fn demonstrated_probability(runs: usize, confidence: f64) -> f64 {
    if runs == 0 {
        return 0.0;
    }
    (1.0 - confidence).powf(1.0 / runs as f64)
}

/// The one-sided upper confidence bound of a per-run probability from `failures` among
/// `runs` (Clopper–Pearson 1934): the p with P(Binomial(n, p) ≤ x) = 1 − C, the largest
/// probability still consistent with so few failures. With no failure it is 1 − (1 − C)^(1/n),
/// the zero-failure bound of [`demonstrated_probability`]; otherwise the monotone CDF is
/// bisected to the last bit. 1 for no runs (nothing is shown) or all runs failed.
pub fn failure_probability_bound(failures: usize, runs: usize, confidence: f64) -> f64 {
    if runs == 0 || failures >= runs || !in_open_unit(confidence) {
        return 1.0;
    }
    if failures == 0 {
        return 1.0 - demonstrated_probability(runs, confidence);
    }
    let alpha = 1.0 - confidence;
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    // 64 halvings take the bracket below one ulp of any probability in (0, 1).
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if binomial_cdf_at(runs, mid, failures) > alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The rank r (1-based, from the extreme) of the order statistic that bounds the
/// `probability` quantile of the tail with at least `confidence` among `runs` samples: the
/// largest r with P(Binomial(n, 1 − p) ≥ r) ≥ C. `None` when even the extreme sample does
/// not (too few runs). The same rank serves a lower bound (r-th smallest) and an upper bound
/// (r-th largest).
pub fn bound_rank(runs: usize, probability: f64, confidence: f64) -> Option<usize> {
    if runs == 0 || !(in_open_unit(probability) && in_open_unit(confidence)) {
        return None;
    }
    let cdf = binomial_cdf(runs, 1.0 - probability);
    // P(B ≥ r) = 1 − F(r − 1), non-increasing in r.
    (1..=runs)
        .take_while(|&r| 1.0 - cdf[r - 1] >= confidence)
        .last()
}

/// The equal-tailed confidence interval of the q-quantile from `n` sorted samples: 1-based
/// ranks (l, u) with F(l − 1) ≤ α/2 and F(u − 1) ≥ 1 − α/2 (α = 1 − C), l as large and u as
/// small as that allows, so that the coverage F(u − 1) − F(l − 1) is at least C. A side is
/// `None` when no sample is far enough out to bound it at that confidence.
pub fn quantile_ci_ranks(n: usize, q: f64, confidence: f64) -> (Option<usize>, Option<usize>) {
    if n == 0 || !in_open_unit(confidence) {
        return (None, None);
    }
    let cdf = binomial_cdf(n, q.clamp(0.0, 1.0));
    let tail = 0.5 * (1.0 - confidence);
    let low = (1..=n).take_while(|&l| cdf[l - 1] <= tail).last();
    let high = (1..=n).find(|&u| cdf[u - 1] >= 1.0 - tail);
    (low, high)
}

/// F(k) = P(Binomial(n, q) ≤ k) for k = 0..=n. The terms are summed from their logarithms
/// (scaled by the largest), so that n in the hundreds of thousands neither under- nor
/// overflows.
pub fn binomial_cdf(n: usize, q: f64) -> Vec<f64> {
    if q <= 0.0 {
        return vec![1.0; n + 1];
    }
    if q >= 1.0 {
        let mut f = vec![0.0; n + 1];
        f[n] = 1.0;
        return f;
    }
    let log_pmf = log_pmf(n, q, n);
    let top = log_pmf.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut acc = 0.0;
    let mut cdf: Vec<f64> = log_pmf
        .iter()
        .map(|&l| {
            acc += (l - top).exp();
            acc
        })
        .collect();
    let total = acc;
    for c in cdf.iter_mut() {
        *c = (*c / total).min(1.0);
    }
    cdf
}

/// P(Binomial(n, q) ≤ x) for 0 < q < 1, summed over the x + 1 terms alone (from their
/// logarithms, largest first), so that a campaign of a million runs with few failures costs
/// x terms per call, not n.
fn binomial_cdf_at(n: usize, q: f64, x: usize) -> f64 {
    let logs = log_pmf(n, q, x.min(n));
    let top = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (top + logs.iter().map(|&l| (l - top).exp()).sum::<f64>().ln())
        .exp()
        .min(1.0)
}

/// ln P(Binomial(n, q) = k) for k = 0..=upto (upto ≤ n, 0 < q < 1), by the ratio of
/// consecutive terms from ln (1 − q)ⁿ.
fn log_pmf(n: usize, q: f64, upto: usize) -> Vec<f64> {
    let ratio = (q / (1.0 - q)).ln();
    let mut l = n as f64 * (-q).ln_1p();
    let mut logs = Vec::with_capacity(upto + 1);
    logs.push(l);
    for k in 0..upto {
        l += ((n - k) as f64 / (k + 1) as f64).ln() + ratio;
        logs.push(l);
    }
    logs
}

fn in_open_unit(x: f64) -> bool {
    x > 0.0 && x < 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Wilks' zero-failure run counts. 0.95/0.95: ln 0.05/ln 0.95 = 58.40 → 59 (the classic
    /// "59 runs" of the GRS/BEPU literature). 0.9973/0.95: ln 0.05/ln 0.9973 =
    /// −2.995732/−0.0027036516 = 1108.03, so the exact count is 1109: 1108 runs give
    /// 1 − 0.9973¹¹⁰⁸ = 0.949996, a hair short of 0.95, and 1109 give 0.950131. The "1108"
    /// quoted for 3σ/95% is that ratio rounded to the nearest integer instead of up.
    #[test]
    fn wilks_run_counts_follow_the_exact_inequality() {
        assert_eq!(runs_needed(0.95, 0.95), Some(59));
        assert_eq!(runs_needed(0.9973, 0.95), Some(1109));
        assert!(1.0 - 0.9973f64.powi(1108) < 0.95);
        assert!(1.0 - 0.9973f64.powi(1109) >= 0.95);
        // 0.99/0.95: ln 0.05/ln 0.99 = 298.07 → 299 (same tables).
        assert_eq!(runs_needed(0.99, 0.95), Some(299));
        assert_eq!(runs_needed(1.0, 0.95), None);
        assert_eq!(runs_needed(0.95, 0.0), None);
    }

    /// Higher-order Wilks counts, one-sided 95/95 (Wilks 1941; the table of Guba, Makai & Pal,
    /// Reliab. Eng. Syst. Saf. 80, 2003): the 2nd, 3rd and 4th extreme need 93, 124 and 153
    /// runs. So 92 runs allow rank 1, 93 runs rank 2, 153 runs rank 4.
    #[test]
    fn bound_ranks_match_the_published_higher_order_counts() {
        assert_eq!(bound_rank(58, 0.95, 0.95), None);
        assert_eq!(bound_rank(59, 0.95, 0.95), Some(1));
        assert_eq!(bound_rank(92, 0.95, 0.95), Some(1));
        assert_eq!(bound_rank(93, 0.95, 0.95), Some(2));
        assert_eq!(bound_rank(124, 0.95, 0.95), Some(3));
        assert_eq!(bound_rank(153, 0.95, 0.95), Some(4));
        assert_eq!(bound_rank(1108, 0.9973, 0.95), None);
        assert_eq!(bound_rank(1109, 0.9973, 0.95), Some(1));
    }

    /// (1 − C)^(1/n): 59 runs demonstrate 0.95049 at 95% (by hand: 0.05^(1/59)), 60 runs
    /// 0.951297.
    #[test]
    fn the_demonstrated_probability_inverts_the_run_count() {
        assert!((demonstrated_probability(59, 0.95) - 0.950_492_390).abs() < 1e-9);
        assert!((demonstrated_probability(60, 0.95) - 0.951_297_1).abs() < 1e-7);
        assert_eq!(demonstrated_probability(0, 0.95), 0.0);
    }

    /// Clopper–Pearson upper bounds at 95%, against scipy.stats.beta.ppf(0.95, x + 1, n − x)
    /// (scipy 1.x, the beta-quantile form of the same bound): 1 of 59 → 0.0778979215188183,
    /// 1 of 1109 → 0.004270391931803317, 3 of 1109 → 0.006976603086965753, 2 of 20 →
    /// 0.28261852488586087; none of 1109 → 0.0026976462951569568 (= 1 − 0.05^(1/1109)).
    /// Tolerance 1e-9 relative: the bisection ends at one ulp, the CDF's summed logarithms
    /// carry a few 1e-13.
    #[test]
    fn failure_bounds_match_the_beta_quantiles() {
        let cases = [
            (1, 59, 0.0778979215188183),
            (1, 1109, 0.004270391931803317),
            (3, 1109, 0.006976603086965753),
            (2, 20, 0.28261852488586087),
            (0, 1109, 0.0026976462951569568),
        ];
        for (x, n, want) in cases {
            let got = failure_probability_bound(x, n, 0.95);
            assert!(
                (got / want - 1.0).abs() < 1e-9,
                "{x} of {n}: {got} vs {want}"
            );
        }
        // The x-term sum agrees with the full CDF.
        let full = binomial_cdf(1109, 0.004);
        for x in [1, 3, 10] {
            assert!((binomial_cdf_at(1109, 0.004, x) / full[x] - 1.0).abs() < 1e-12);
        }
        assert_eq!(failure_probability_bound(0, 0, 0.95), 1.0);
        assert_eq!(failure_probability_bound(5, 5, 0.95), 1.0);
    }

    /// The median of 10 samples: the 95% interval is [x₍₂₎, x₍₉₎] with coverage
    /// 1013/1024 − 11/1024 = 0.9785 (Conover, Table A3; by hand from Binomial(10, ½)).
    /// The 0.27% quantile of 360 samples: F(0) = 0.9973³⁶⁰ = 0.378 > 0.025, so no sample bounds
    /// it from below; above, F(3) = 0.983 ≥ 0.975 > F(2) = 0.925, so x₍₄₎.
    #[test]
    fn quantile_intervals_come_from_binomial_ranks() {
        assert_eq!(quantile_ci_ranks(10, 0.5, 0.95), (Some(2), Some(9)));
        assert_eq!(quantile_ci_ranks(360, 0.0027, 0.95), (None, Some(4)));
        let f = binomial_cdf(10, 0.5);
        assert!((f[1] - 11.0 / 1024.0).abs() < 1e-15);
        assert!((f[8] - 1013.0 / 1024.0).abs() < 1e-14);
        // A large n neither under- nor overflows: the median of 600 000 is bracketed.
        let (l, u) = quantile_ci_ranks(600_000, 0.5, 0.95);
        assert!(l.unwrap() < 300_000 && u.unwrap() > 300_000);
    }
}
