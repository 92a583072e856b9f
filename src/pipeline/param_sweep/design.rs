//! The points of a sweep: every combination of a grid's values (the first key varies slowest),
//! or a Latin hypercube: each key's range cut into `points` equal strata, one point per stratum
//! and key, strata paired by a seeded random permutation per key (McKay, Beckman and Conover,
//! Technometrics 21, 1979), the value uniform within its stratum.

use crate::spec::sweep::{SweepMethod, SweepSpec};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

/// The swept keys and the value of each at each point (`points[p][j]` is key `j` at point `p`).
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    pub keys: Vec<String>,
    pub points: Vec<Vec<f64>>,
}

impl Design {
    /// The points `spec` describes (a validated `[sweep]`).
    pub fn of(spec: &SweepSpec) -> Design {
        let keys = spec.parameter.iter().map(|p| p.key.clone()).collect();
        let points = match spec.method {
            SweepMethod::Grid => grid(
                &spec
                    .parameter
                    .iter()
                    .map(|p| p.grid_values())
                    .collect::<Vec<_>>(),
            ),
            SweepMethod::Lhs => {
                let bounds: Vec<[f64; 2]> = spec
                    .parameter
                    .iter()
                    .map(|p| p.bounds.unwrap_or([0.0, 1.0]))
                    .collect();
                latin_hypercube(&bounds, spec.points.unwrap_or(1), spec.seed)
            }
        };
        Design { keys, points }
    }
}

/// The full factorial of `values`, the first axis varying slowest.
fn grid(values: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut points = vec![Vec::new()];
    for axis in values {
        points = points
            .into_iter()
            .flat_map(|p| {
                axis.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(*v);
                    q
                })
            })
            .collect();
    }
    points
}

/// Uniform in [0, 1) from the top 53 bits of the stream.
fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// `n` points in the box `bounds`: per key a Fisher–Yates permutation of the strata, then the
/// offsets within them, all from one ChaCha8 stream of `seed` drawn in that order.
fn latin_hypercube(bounds: &[[f64; 2]], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut points = vec![Vec::with_capacity(bounds.len()); n];
    for &[lo, hi] in bounds {
        let mut strata: Vec<usize> = (0..n).collect();
        for k in (1..n).rev() {
            let j = ((uniform(&mut rng) * (k + 1) as f64) as usize).min(k);
            strata.swap(k, j);
        }
        for (p, s) in points.iter_mut().zip(&strata) {
            let t = (*s as f64 + uniform(&mut rng)) / n as f64;
            p.push(lo + (hi - lo) * t);
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_varies_the_first_key_slowest() {
        let g = grid(&[vec![1.0, 2.0], vec![10.0, 20.0, 30.0]]);
        assert_eq!(
            g,
            vec![
                vec![1.0, 10.0],
                vec![1.0, 20.0],
                vec![1.0, 30.0],
                vec![2.0, 10.0],
                vec![2.0, 20.0],
                vec![2.0, 30.0]
            ]
        );
    }

    /// The defining property of a Latin hypercube (McKay et al. 1979): projected on any key,
    /// the n points fall one in each of the n equal strata of its range.
    #[test]
    fn latin_hypercube_puts_one_point_in_each_stratum_of_every_key() {
        let bounds = [[0.0, 1.0], [-2.0, 6.0], [100.0, 101.0]];
        let n = 17;
        let pts = latin_hypercube(&bounds, n, 5);
        assert_eq!(pts.len(), n);
        for (j, [lo, hi]) in bounds.iter().enumerate() {
            let mut strata: Vec<usize> = pts
                .iter()
                .map(|p| ((p[j] - lo) / (hi - lo) * n as f64) as usize)
                .collect();
            strata.sort();
            assert_eq!(strata, (0..n).collect::<Vec<_>>(), "key {j}");
        }
        assert_eq!(
            pts,
            latin_hypercube(&bounds, n, 5),
            "same seed, same points"
        );
        assert_ne!(
            pts,
            latin_hypercube(&bounds, n, 6),
            "another seed, other points"
        );
    }
}
