//! Physical constants and unit helpers shared by every layer: standard gravity, decibels,
//! octaves and log-log interpolation of `[f, value]` tables (the format of test profiles).

/// Standard gravity, m/s² (ISO 80000-3 / CGPM 1901).
pub const G: f64 = 9.80665;

/// Converts m/s² to g.
pub fn to_g(a_m_s2: f64) -> f64 {
    a_m_s2 / G
}

/// Converts g to m/s².
pub fn from_g(a_g: f64) -> f64 {
    a_g * G
}

/// Power ratio in dB (10·log10), as used for PSD tolerance bands.
pub fn db_power(ratio: f64) -> f64 {
    10.0 * ratio.log10()
}

/// Amplitude ratio in dB (20·log10).
pub fn db_amplitude(ratio: f64) -> f64 {
    20.0 * ratio.log10()
}

/// Number of octaves between two frequencies.
pub fn octaves(f1: f64, f2: f64) -> f64 {
    (f2 / f1).log2()
}

/// Log-log interpolation in a table of `(x, y)` points with increasing `x` and positive values.
/// Outside the table the result is 0: a test profile defines no energy outside its band.
pub fn loglog_interp(table: &[(f64, f64)], x: f64) -> f64 {
    if table.is_empty() || x < table[0].0 || x > table[table.len() - 1].0 {
        return 0.0;
    }
    let i =
        match table.binary_search_by(|p| p.0.partial_cmp(&x).unwrap_or(std::cmp::Ordering::Less)) {
            Ok(i) => return table[i].1,
            Err(i) => i,
        };
    let (x0, y0) = table[i - 1];
    let (x1, y1) = table[i];
    if y0 <= 0.0 || y1 <= 0.0 {
        // A zero level cannot be interpolated in log space: fall back to linear.
        return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
    }
    let slope = (y1 / y0).ln() / (x1 / x0).ln();
    y0 * (x / x0).powf(slope)
}

/// Exact integral of a log-log segment table from its first to its last point: the mean square
/// of a PSD profile (g² for a g²/Hz profile). Each segment is y = y0·(x/x0)^s, integrated in
/// closed form, so no quadrature error enters a Grms figure.
pub fn loglog_integral(table: &[(f64, f64)]) -> f64 {
    let mut sum = 0.0;
    for w in table.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if y0 <= 0.0 || y1 <= 0.0 {
            sum += 0.5 * (y0 + y1) * (x1 - x0);
            continue;
        }
        let s = (y1 / y0).ln() / (x1 / x0).ln();
        if (s + 1.0).abs() < 1e-12 {
            sum += y0 * x0 * (x1 / x0).ln();
        } else {
            sum += y0 * x0 / (s + 1.0) * ((x1 / x0).powf(s + 1.0) - 1.0);
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gevs_profile_is_14_1_grms() {
        // GSFC-STD-7000A Table 2.4-3 qualification level: 14.1 Grms.
        let p = [(20.0, 0.026), (50.0, 0.16), (800.0, 0.16), (2000.0, 0.026)];
        let grms = loglog_integral(&p).sqrt();
        assert!((grms - 14.1).abs() < 0.05, "{grms}");
    }

    #[test]
    fn loglog_interp_follows_slope() {
        // +6 dB/oct doubles... a 0.026 -> 0.16 rise over 20 -> 50 Hz; midpoint in log space.
        let p = [(20.0, 0.026), (50.0, 0.16)];
        let xm = (20.0f64 * 50.0).sqrt();
        let ym = loglog_interp(&p, xm);
        assert!((ym - (0.026f64 * 0.16).sqrt()).abs() < 1e-12);
        assert_eq!(loglog_interp(&p, 10.0), 0.0);
    }
}
