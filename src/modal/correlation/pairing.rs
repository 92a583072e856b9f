//! Which FE mode each test mode is. With shapes that can tell modes apart, the pairing is by
//! MAC; with at most one channel per axis a shape is a handful of numbers that every mode
//! matches, so the pairing is by frequency among the FE modes whose effective mass lies along
//! the axis the test mode moves in most.

use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PairingMethod {
    /// Largest MAC first, one FE mode per test mode.
    Mac,
    /// Nearest frequency among the FE modes of the test mode's effective-mass direction.
    FrequencyAndDirection,
}

/// Test mode `test` is FE mode `fe` (indices into the lists given).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pair {
    pub test: usize,
    pub fe: usize,
}

/// Greedy assignment on the MAC matrix (test rows, FE columns): the largest remaining MAC is
/// paired first, each mode at most once; a test mode left without an FE mode (more test modes
/// than FE modes) is unpaired. Result in test-mode order.
pub fn by_mac(mac: &[Vec<f64>]) -> Vec<Pair> {
    let mut cells: Vec<(usize, usize)> = (0..mac.len())
        .flat_map(|i| (0..mac[i].len()).map(move |j| (i, j)))
        .collect();
    // Ties go to the lower test, then FE index, so the pairing is deterministic.
    cells.sort_by(|a, b| mac[b.0][b.1].total_cmp(&mac[a.0][a.1]).then(a.cmp(b)));
    let mut test_used = vec![false; mac.len()];
    let mut fe_used = vec![false; mac.first().map_or(0, Vec::len)];
    let mut pairs = Vec::new();
    for (i, j) in cells {
        if !test_used[i] && !fe_used[j] {
            test_used[i] = true;
            fe_used[j] = true;
            pairs.push(Pair { test: i, fe: j });
        }
    }
    pairs.sort_by_key(|p| p.test);
    pairs
}

/// For each test mode in order, the FE mode of the same axis (0, 1, 2) nearest in frequency
/// (relative distance) not yet taken; `fe_axis` is each FE mode's dominant translational
/// effective-mass direction. A test mode with no FE mode along its axis is unpaired.
pub fn by_frequency_and_direction(
    test_hz: &[f64],
    test_axis: &[usize],
    fe_hz: &[f64],
    fe_axis: &[Option<usize>],
) -> Vec<Pair> {
    let mut used = vec![false; fe_hz.len()];
    let mut pairs = Vec::new();
    for (i, (&f, &axis)) in test_hz.iter().zip(test_axis).enumerate() {
        let best = (0..fe_hz.len())
            .filter(|&j| !used[j] && fe_axis[j] == Some(axis))
            .min_by(|&a, &b| {
                let d = |j: usize| ((fe_hz[j] - f) / f).abs();
                d(a).total_cmp(&d(b))
            });
        if let Some(j) = best {
            used[j] = true;
            pairs.push(Pair { test: i, fe: j });
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mac_pairing_takes_the_largest_mac_first() {
        // Test 0 resembles FE 1 most, test 1 resembles FE 1 a bit less and FE 0 next.
        let mac = vec![vec![0.2, 0.95], vec![0.8, 0.9]];
        let p = by_mac(&mac);
        assert_eq!(p, vec![Pair { test: 0, fe: 1 }, Pair { test: 1, fe: 0 }]);
    }

    #[test]
    fn frequency_pairing_keeps_to_the_axis() {
        let p = by_frequency_and_direction(
            &[10.0, 30.0],
            &[2, 2],
            &[10.1, 11.0, 29.0],
            &[Some(2), Some(1), Some(2)],
        );
        assert_eq!(p, vec![Pair { test: 0, fe: 0 }, Pair { test: 1, fe: 2 }]);
    }
}
