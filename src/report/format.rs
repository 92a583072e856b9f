//! Numbers with their units as the report and the console print them.

/// A number for a table: four decimals, or scientific notation when very large or small;
/// a dash for a non-finite value.
pub fn number(v: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.4e}")
    } else {
        format!("{v:.4}")
    }
}

/// A value with its unit for a table; stresses in MPa, which reads better than Pa.
pub fn quantity(v: f64, unit: &str) -> String {
    match unit {
        "" => number(v),
        "Pa" => format!("{} MPa", number(v / 1e6)),
        _ if !v.is_finite() => number(v),
        _ => format!("{} {unit}", number(v)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stresses read in MPa, frequencies and forces as given, large counts in scientific
    /// notation, a non-finite value as a dash (the console's gate lines use the same).
    #[test]
    fn quantities_read_in_engineering_units() {
        assert_eq!(quantity(92_858_408.653_8, "Pa"), "92.8584 MPa");
        assert_eq!(quantity(6.305_1, "Hz"), "6.3051 Hz");
        assert_eq!(quantity(93_868.380_8, "N"), "93868.3808 N");
        assert_eq!(quantity(2.5e9, "N/m"), "2.5000e9 N/m");
        assert_eq!(quantity(f64::NAN, "N"), "–");
        assert_eq!(number(50.641_9), "50.6419");
    }
}
