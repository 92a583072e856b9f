//! Plausible ranges of the physical inputs. A value outside its range is a typo, a unit slip
//! or a mutated file: no result computed from it would mean anything, and a subnormal or
//! overflowing value can stall a solver (a Young's modulus of 1e-300 never converges). The
//! ranges are wide (any structural material, any satellite stack) and documented in
//! docs/robustness.md; a value outside one is refused with the key and the range.

use super::Locator;
use crate::error::SpecError;

/// A closed range `[lo, hi]` in `unit`; `zero` also admits exactly 0 (an absent term).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
    pub unit: &'static str,
    pub zero: bool,
}

const fn range(lo: f64, hi: f64, unit: &'static str, zero: bool) -> Range {
    Range { lo, hi, unit, zero }
}

/// From soft elastomers (0.1 MPa) to above diamond (1.2 TPa).
pub const YOUNGS_MODULUS_PA: Range = range(1e5, 1e13, "Pa", false);
/// From foams and aerogels to above osmium (22.6 t/m³).
pub const DENSITY_KG_M3: Range = range(1.0, 1e5, "kg/m³", false);
/// Yield and ultimate strengths.
pub const STRENGTH_PA: Range = range(1e5, 1e11, "Pa", false);
/// A lumped mass: a sensor to a launcher stage.
pub const MASS_KG: Range = range(1e-9, 1e9, "kg", true);
/// A lumped rotary inertia.
pub const INERTIA_KG_M2: Range = range(1e-15, 1e12, "kg·m²", true);
/// A spring or joint stiffness (N/m or N·m/rad). Penalty springs model rigid ties: the modal
/// solvers handle ties 1e15 times stiffer than the elements they join (8.4e22 N/m on a steel
/// beam, with a MAXRATIO warning naming the spring), so the bound sits above that.
pub const STIFFNESS: Range = range(1e-6, 1e25, "N/m or N·m/rad", true);
/// A preload force.
pub const FORCE_N: Range = range(1e-6, 1e10, "N", false);
/// A coordinate or a length of the model.
pub const LENGTH_M: Range = range(1e-9, 1e5, "m", false);
/// A node coordinate (magnitude).
pub const COORDINATE_M: Range = range(0.0, 1e5, "m", true);
/// The amplification Q = 1/(2ζ): above critical damping, below any real structure's.
pub const Q: Range = range(0.5, 1e4, "", false);
/// The damping ratio ζ.
pub const ZETA: Range = range(5e-5, 0.999, "", false);
/// A base-excitation sine level.
pub const ACCELERATION_G: Range = range(1e-6, 1e4, "g", false);
/// A base-excitation sine displacement amplitude, zero to peak. The largest shakers that
/// test spacecraft travel ±0.05–0.07 m (electrodynamic 100 mm stroke; hydraulic tables);
/// 0.1 m covers them, and a displacement typed in millimetres (1.17 for 1.17 mm) is caught.
pub const DISPLACEMENT_M: Range = range(1e-12, 0.1, "m", false);
/// A random-vibration PSD level.
pub const PSD_G2_HZ: Range = range(1e-15, 1e6, "g²/Hz", false);
/// A test duration.
pub const DURATION_S: Range = range(1e-3, 1e8, "s", false);
/// A separation spring: soft coil springs to stiff disc springs. Above, the integrator's step
/// shrinks with 1/√k and the run takes minutes.
pub const SEPARATION_SPRING_N_M: Range = range(1e-3, 1e7, "N/m", false);
/// A separation spring's relative stiffness error (magnitude; above −1 checked apart).
pub const STIFFNESS_ERROR: Range = range(0.0, 10.0, "", true);
/// A separation spring's stroke.
pub const STROKE_M: Range = range(1e-6, 10.0, "m", false);
/// The simulated time of a release.
pub const SEPARATION_TIME_S: Range = range(1e-6, 1e5, "s", false);
/// The bar modes' damping ratio in a release (0: undamped); an overdamped ratio made the
/// integrator take millions of steps.
pub const BAR_ZETA: Range = range(5e-5, 0.999, "", true);
/// A frequency of the analysis.
pub const FREQUENCY_HZ: Range = range(1e-6, 1e7, "Hz", false);
/// A factor of safety or fitting factor: the standards use 1.0–2.0 (NASA-STD-5001B Table 1,
/// NASA-STD-5020B); 10 is far beyond any of them.
pub const SAFETY_FACTOR: Range = range(1.0, 10.0, "", false);
/// A friction coefficient: lubricated PTFE (~0.04) to clean metal in vacuum (~1.5).
pub const FRICTION: Range = range(1e-3, 2.0, "", false);
/// A friction coefficient of the release's contacts, where 0 (frictionless) is a model
/// choice; 1e5 made a release take 50 s of stick-slip steps.
pub const CONTACT_FRICTION: Range = range(1e-3, 2.0, "", true);
/// A sampling rate: one sample in 11.6 days up to 1 GHz (far beyond any accelerometer or
/// shock recorder). The signal readers hold every rate to it, whatever stated it.
pub const SAMPLING_RATE_HZ: Range = range(1e-6, 1e9, "Hz", false);
/// A satellite's size in a stack (its pitch, the spacing of its columns): the widest launcher
/// fairing is 9 m across. A stack typed in millimetres reads 500 m here.
pub const SATELLITE_SIZE_M: Range = range(1e-9, 10.0, "m", false);
/// A column or guide-bar diameter of a stack.
pub const STACK_DIAMETER_M: Range = range(1e-9, 2.0, "m", false);
/// A length of the `[stack]`: a kilometre-high stack is beyond any launcher (a 200-satellite
/// stack's bars are 110 m); a 100 km bar made a release take 46 s to simulate nothing.
pub const STACK_LENGTH_M: Range = range(1e-9, 1e3, "m", false);

impl Range {
    /// Whether `v` is accepted: finite and inside the range, or exactly 0 where admitted.
    pub fn admits(&self, v: f64) -> bool {
        (self.zero && v == 0.0) || (self.lo..=self.hi).contains(&v)
    }

    pub fn describe(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        let zero = if self.zero { " (or 0)" } else { "" };
        format!("[{:e}, {:e}]{unit}{zero}", self.lo, self.hi)
    }
}

/// Checks `v` against `r`; the error names the key, the value and the range.
pub fn check(loc: &Locator, key: &str, v: f64, r: Range) -> Result<(), SpecError> {
    if r.admits(v) {
        Ok(())
    } else {
        Err(loc.err(
            key,
            format!(
                "{} is outside the plausible range {} (see docs/robustness.md)",
                readable(v),
                r.describe()
            ),
        ))
    }
}

/// A value as typed: decimal between 1e-3 and 1e6, else with an exponent (a slipped unit
/// reads `1e-12`, not `0.000000000001`).
fn readable(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_refuse_non_finite_subnormal_and_overflowing_values() {
        for v in [f64::NAN, f64::INFINITY, -1.0, 1e-300, 4e-320, 1.7e308] {
            assert!(!YOUNGS_MODULUS_PA.admits(v), "{v}");
        }
        // Steel (200 GPa, handbook value) and aluminium (71.7 GPa) are admitted.
        assert!(YOUNGS_MODULUS_PA.admits(200e9) && YOUNGS_MODULUS_PA.admits(71.7e9));
        assert!(STIFFNESS.admits(0.0) && !YOUNGS_MODULUS_PA.admits(0.0));
        assert!(!Q.admits(f64::NAN) && Q.admits(15.0) && !Q.admits(1e300));
    }
}
