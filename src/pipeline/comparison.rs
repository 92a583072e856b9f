//! The comparison with the paper's measured and simulated values (Aerospace 2022): what the
//! report sets beside satqual's numbers so that an engineer sees how far the model is from
//! the hardware.

use crate::modal::ModalResult;
use crate::response::SineAxis;
use crate::results::PaperComparison;
use crate::separation::SeparationResult;

const SHAKER_TEST: &str = "paper §5.1.1, Fig. 17a";

/// Per sine axis, the top satellite's peak against the 2-satellite shaker test.
pub fn sine_peaks(axes: &[SineAxis]) -> Vec<PaperComparison> {
    axes.iter()
        .filter_map(|a| {
            let measured = match a.axis.as_str() {
                "x" => "29.1 Hz, 4.53 g",
                "y" => "31.2 Hz, 4.29 g",
                _ => "77.6 Hz, 0.68 g",
            };
            let p = a.peaks.iter().find(|p| p.name == "sat 1")?;
            Some(PaperComparison {
                quantity: format!("sine peak response along {} (top satellite)", a.axis),
                paper: format!("{measured} (measured)"),
                satqual: format!("{:.2} Hz, {:.2} g", p.frequency_hz, p.acceleration_g),
                source: SHAKER_TEST.into(),
            })
        })
        .collect()
}

/// Per direction, the mode of largest effective mass against the shaker test's resonance.
pub fn resonances(r: &ModalResult) -> Vec<PaperComparison> {
    [("x", 0usize, 29.1), ("y", 1, 31.2), ("z", 2, 77.6)]
        .into_iter()
        .filter_map(|(label, dir, measured)| {
            let fraction = |m: &crate::modal::Mode| m.effective_mass_fraction.to_array()[dir];
            let m = r
                .modes
                .iter()
                .max_by(|a, b| fraction(a).total_cmp(&fraction(b)))?;
            Some(PaperComparison {
                quantity: format!("first {label} resonance (2-satellite shaker test)"),
                paper: format!("{measured} Hz (measured)"),
                satqual: format!("{:.2} Hz (mode {})", m.frequency_hz, m.index),
                source: SHAKER_TEST.into(),
            })
        })
        .collect()
}

/// Separation speeds, rates and exit time against the paper's simulation and test.
pub fn separation(result: &SeparationResult) -> Vec<PaperComparison> {
    let sats = &result.satellites;
    let vmax = sats.iter().map(|s| s.max_speed_m_s).fold(0.0, f64::max);
    let vmin = sats
        .iter()
        .map(|s| s.final_speed_m_s)
        .fold(f64::INFINITY, f64::min);
    let vmx = sats.iter().map(|s| s.final_speed_m_s).fold(0.0, f64::max);
    let line = |quantity: String, paper: &str, satqual: String, source: &str| PaperComparison {
        quantity,
        paper: paper.into(),
        satqual,
        source: source.into(),
    };
    let mut out = vec![
        line(
            "maximum separation speed".into(),
            "0.347 m/s (simulated)",
            format!("{vmax:.4} m/s"),
            "paper §4, Fig. 15",
        ),
        line(
            "exit speed with 10% spring error".into(),
            "0.278 m/s simulated, 0.252 m/s test",
            format!("{vmin:.3}–{vmx:.3} m/s"),
            "paper §5.2, Fig. 20b",
        ),
    ];
    if let Some(s1) = sats.first() {
        out.push(line(
            "first satellite angular rate".into(),
            "2.47 deg/s at separation (simulated)",
            format!(
                "{:.2} deg/s at exit, {:.2} deg/s peak",
                s1.final_rate_deg_s, s1.peak_rate_deg_s
            ),
            "paper §4",
        ));
    }
    if let Some(last) = sats.last()
        && let Some(t) = last.exit_time_s
    {
        out.push(line(
            format!("time for satellite {} to clear the bars", last.index),
            "about 9.5 s",
            format!("{t:.2} s"),
            "paper §4, Fig. 12",
        ));
    }
    out
}
