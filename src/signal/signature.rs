//! Pre/post test signature comparison: the resonances of a low-level signature taken before a
//! qualification test are matched to those taken after it, and each mode's frequency shift and
//! amplitude change are checked against the usual intact-structure criterion (shift ≤ 5%,
//! amplitude change ≤ 20%). Inputs: resonance lists from [`super::frf::resonances`] (or from
//! sweep tracking), one per signature.

use super::frf::Resonance;
use serde::Serialize;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignatureCriteria {
    pub max_shift_pct: f64,
    pub max_amp_change_pct: f64,
    /// A before-mode is matched to the nearest after-peak within this distance, percent.
    pub match_window_pct: f64,
}

impl Default for SignatureCriteria {
    fn default() -> Self {
        SignatureCriteria {
            max_shift_pct: 5.0,
            max_amp_change_pct: 20.0,
            match_window_pct: 25.0,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeComparison {
    /// 1-based, in order of the before-signature's frequencies.
    pub mode: usize,
    pub before_hz: f64,
    /// `None`: no resonance found after the test within the matching window.
    pub after_hz: Option<f64>,
    pub shift_pct: Option<f64>,
    pub amplitude_change_pct: Option<f64>,
    pub pass: bool,
    /// Why the mode fails, empty when it passes.
    pub reason: String,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignatureReport {
    pub criteria: SignatureCriteria,
    pub modes: Vec<ModeComparison>,
    /// Modes found after the test that match nothing before it.
    pub new_after_hz: Vec<f64>,
    pub pass: bool,
    /// One line per failing mode, naming it.
    pub failures: Vec<String>,
}

/// Matches modes by nearest frequency (closest pairs first, each used once) and checks them.
pub fn compare_signatures(
    before: &[Resonance],
    after: &[Resonance],
    crit: &SignatureCriteria,
) -> SignatureReport {
    let mut b: Vec<&Resonance> = before.iter().collect();
    b.sort_by(|x, y| x.frequency_hz.total_cmp(&y.frequency_hz));
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, m) in b.iter().enumerate() {
        for (j, a) in after.iter().enumerate() {
            let d = (a.frequency_hz - m.frequency_hz).abs() / m.frequency_hz * 100.0;
            if d <= crit.match_window_pct {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut match_of: Vec<Option<usize>> = vec![None; b.len()];
    let mut used = vec![false; after.len()];
    for (_, i, j) in pairs {
        if match_of[i].is_none() && !used[j] {
            match_of[i] = Some(j);
            used[j] = true;
        }
    }
    let mut modes = Vec::new();
    let mut failures = Vec::new();
    for (i, m) in b.iter().enumerate() {
        let mode = i + 1;
        let cmp = match match_of[i] {
            None => {
                let reason = format!(
                    "no resonance within ±{}% after the test",
                    crit.match_window_pct
                );
                ModeComparison {
                    mode,
                    before_hz: m.frequency_hz,
                    after_hz: None,
                    shift_pct: None,
                    amplitude_change_pct: None,
                    pass: false,
                    reason,
                }
            }
            Some(j) => {
                let a = &after[j];
                let shift = 100.0 * (a.frequency_hz - m.frequency_hz) / m.frequency_hz;
                let amp = 100.0 * (a.magnitude - m.magnitude) / m.magnitude;
                let mut why = Vec::new();
                if shift.abs() > crit.max_shift_pct {
                    why.push(format!(
                        "frequency shift {shift:+.2}% exceeds ±{}%",
                        crit.max_shift_pct
                    ));
                }
                if amp.abs() > crit.max_amp_change_pct {
                    why.push(format!(
                        "amplitude change {amp:+.2}% exceeds ±{}%",
                        crit.max_amp_change_pct
                    ));
                }
                ModeComparison {
                    mode,
                    before_hz: m.frequency_hz,
                    after_hz: Some(a.frequency_hz),
                    shift_pct: Some(shift),
                    amplitude_change_pct: Some(amp),
                    pass: why.is_empty(),
                    reason: why.join("; "),
                }
            }
        };
        if !cmp.pass {
            failures.push(format!(
                "mode {} at {:.2} Hz: {}",
                cmp.mode, cmp.before_hz, cmp.reason
            ));
        }
        modes.push(cmp);
    }
    let mut new_after_hz: Vec<f64> = after
        .iter()
        .zip(&used)
        .filter(|(_, u)| !**u)
        .map(|(a, _)| a.frequency_hz)
        .collect();
    new_after_hz.sort_by(|x, y| x.total_cmp(y));
    SignatureReport {
        criteria: crit.clone(),
        pass: failures.is_empty() && !modes.is_empty(),
        modes,
        new_after_hz,
        failures,
    }
}
