//! Test-analysis correlation gates: the frequency error of every paired mode (±3% by
//! ECSS-E-ST-32-11C or ±5% by NASA-STD-5002, chosen in the scene), and the MAC and the
//! cross-orthogonality of the paired modes: at least 0.9 on the diagonal, at most 0.1 off it.

use super::verdict::{Group, Verdict, at_least, at_most};
use crate::spec::correlation::FrequencyStandard;

const MAC_SOURCE: &str = "test-analysis correlation: MAC ≥ 0.9 for paired modes, ≤ 0.1 between others (ECSS-E-ST-32-11C)";
const ORTHOGONALITY_SOURCE: &str =
    "test-analysis cross-orthogonality ≥ 0.9 diagonal, ≤ 0.1 off-diagonal (NASA-STD-5002)";
pub const MIN_DIAGONAL: f64 = 0.9;
pub const MAX_OFF_DIAGONAL: f64 = 0.1;

/// One paired mode as the gates see it; mode numbers are 1-based.
#[derive(Debug, Clone, Copy)]
pub struct PairedMode {
    pub test_mode: usize,
    pub fe_mode: usize,
    pub test_hz: f64,
    pub fe_hz: f64,
}

impl PairedMode {
    /// (FE − test)/test, %.
    pub fn error_pct(&self) -> f64 {
        (self.fe_hz - self.test_hz) / self.test_hz * 100.0
    }
}

/// |frequency error| of every pair within the standard's tolerance; margin 1 − |e|/tol.
pub fn frequency(pairs: &[PairedMode], standard: FrequencyStandard) -> Vec<Verdict> {
    pairs
        .iter()
        .map(|p| {
            at_most(
                format!(
                    "frequency error, test mode {} / FE mode {} [%]",
                    p.test_mode, p.fe_mode
                ),
                p.error_pct().abs(),
                standard.tolerance_pct(),
                standard.source(),
            )
            .in_group(Group::TestData)
            .with_unit("%")
        })
        .collect()
}

/// A test mode no FE mode could be paired with: a failed gate, never a silent gap.
pub fn unpaired(test_mode: usize, test_hz: f64, why: &str) -> Verdict {
    Verdict::gate(
        format!("test mode {test_mode} at {test_hz:.4} Hz paired with an FE mode ({why})"),
        0.0,
        1.0,
        -1.0,
        false,
        "every test mode must be paired to be correlated",
    )
    .in_group(Group::TestData)
}

/// Which correlation matrix a gate reads.
#[derive(Debug, Clone, Copy)]
pub enum Matrix {
    Mac,
    CrossOrthogonality,
}

impl Matrix {
    fn label(self) -> &'static str {
        match self {
            Matrix::Mac => "MAC",
            Matrix::CrossOrthogonality => "cross-orthogonality",
        }
    }
    fn source(self) -> &'static str {
        match self {
            Matrix::Mac => MAC_SOURCE,
            Matrix::CrossOrthogonality => ORTHOGONALITY_SOURCE,
        }
    }
}

/// `square[i][j]`: the matrix between paired test mode i and paired FE mode j (same order as
/// `pairs`). Per pair: the diagonal at least 0.9, the largest off-diagonal term of its row at
/// most 0.1 (no off-diagonal gate with a single pair).
pub fn matrix(kind: Matrix, square: &[Vec<f64>], pairs: &[PairedMode]) -> Vec<Verdict> {
    let mut out = Vec::new();
    for (i, p) in pairs.iter().enumerate() {
        let modes = format!("test mode {} / FE mode {}", p.test_mode, p.fe_mode);
        out.push(
            at_least(
                format!("{} {modes}", kind.label()),
                square[i][i],
                MIN_DIAGONAL,
                kind.source(),
            )
            .in_group(Group::TestData),
        );
        let off = (0..pairs.len())
            .filter(|&j| j != i)
            .map(|j| square[i][j])
            .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))));
        if let Some(off) = off {
            out.push(
                at_most(
                    format!(
                        "largest off-diagonal {} of test mode {}",
                        kind.label(),
                        p.test_mode
                    ),
                    off,
                    MAX_OFF_DIAGONAL,
                    kind.source(),
                )
                .in_group(Group::TestData),
            );
        }
    }
    out
}
