//! The acceleration recorded at the integrator's accepted steps, put on a uniform time grid
//! for the shock response spectrum.
//!
//! Between two step ends the acceleration is interpolated linearly. The steps follow the
//! forces (the step control shrinks them on every contact pulse, and every onset and exit is a
//! step end), so the recorded points resolve each pulse; the interpolation error is of order
//! h²·a″/8 over a step h. A force switched at a step end (a release, a contact onset or exit)
//! is recorded twice at that time, before and after; the grid takes the value after the
//! switch at that instant (right-continuous), so a release at a grid time starts with its
//! full spring force.

/// Samples of `values` (at the non-decreasing `times`) at `t0 + k/fs`, k = 0..count.
/// Before the first and after the last recorded time the nearest recorded value holds.
pub fn resample(
    times: &[f64],
    values: &[[f64; 3]],
    t0: f64,
    fs: f64,
    count: usize,
) -> Vec<[f64; 3]> {
    let mut out = Vec::with_capacity(count);
    let mut j = 0;
    for k in 0..count {
        let t = t0 + k as f64 / fs;
        // The last record at or before t (the latest of equal times: after the switch).
        while j + 1 < times.len() && times[j + 1] <= t {
            j += 1;
        }
        out.push(interpolate(times, values, j, t));
    }
    out
}

fn interpolate(times: &[f64], values: &[[f64; 3]], j: usize, t: f64) -> [f64; 3] {
    if j + 1 >= times.len() || t <= times[j] {
        return values[j];
    }
    let w = (t - times[j]) / (times[j + 1] - times[j]);
    let (a, b) = (values[j], values[j + 1]);
    [0, 1, 2].map(|i| a[i] + w * (b[i] - a[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp sampled at irregular times comes back exact on the grid (linear interpolation
    /// of a linear function); a jump recorded twice at t = 1 is taken after the switch there.
    #[test]
    fn linear_between_steps_and_right_continuous_at_a_switch() {
        let times = [0.0, 0.3, 1.0, 1.0, 2.0];
        let v = |x: f64| [x, -x, 2.0 * x];
        let values = [v(0.0), v(0.3), v(1.0), v(5.0), v(6.0)];
        let out = resample(&times, &values, 0.0, 4.0, 9);
        for (k, s) in out.iter().enumerate().take(4) {
            let t = k as f64 / 4.0;
            assert!(
                (s[0] - t).abs() < 1e-15 && (s[2] - 2.0 * t).abs() < 1e-15,
                "{k}: {s:?}"
            );
        }
        assert_eq!(out[4], v(5.0));
        assert!((out[6][0] - 5.5).abs() < 1e-15);
        assert_eq!(out[8], v(6.0));
    }
}
