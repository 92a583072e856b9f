//! Why a run needs tiny steps: the stiffest spring and the contact, each with the natural
//! period it gives a satellite and the step that period implies, for the messages of a run
//! that ran out of steps or whose step fell to the round-off floor.

use super::super::params::Model;

/// Steps per period an explicit Runge–Kutta pair needs to follow an oscillation to a tight
/// tolerance (Dormand–Prince 5(4) at 1e-6: about 20–50): the lower end, for an estimate.
const STEPS_PER_PERIOD: f64 = 20.0;

/// Impact speed at which the contact's period is estimated, m/s: the order of the exit speeds
/// (0.1–0.4 m/s) and of the lateral speeds in the bores.
const IMPACT_SPEED_M_S: f64 = 0.1;

/// One sentence naming the stiffest element of the model and the step size it implies.
pub fn stiffest_element(m: &Model) -> String {
    let lightest = m
        .satellites
        .iter()
        .map(|s| s.mass_kg)
        .fold(f64::INFINITY, f64::min);
    let spring = m
        .springs
        .iter()
        .map(|s| (s, period(s.stiffness_n_m, satellite_mass(m, s.interface))))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let contact = contact_period(m, lightest);
    let contact_text = format!(
        "the bore contact (K = {:.3e} N/m^{}, exponent {}) gives a {:.3e} kg satellite a contact time of about {:.3e} s at {IMPACT_SPEED_M_S} m/s",
        m.contact.stiffness, m.contact.exponent, m.contact.exponent, lightest, contact
    );
    match spring {
        Some((s, t)) if t < contact => format!(
            "the stiffest element is the separation spring of interface {} column {} (k = {:.3e} N/m): its period of {t:.3e} s implies steps of about {:.3e} s ({contact_text})",
            s.interface,
            s.column + 1,
            s.stiffness_n_m,
            t / STEPS_PER_PERIOD
        ),
        _ => format!(
            "the stiffest element is the contact: {contact_text}, which implies steps of about {:.3e} s",
            contact / STEPS_PER_PERIOD
        ),
    }
}

/// Mass of the satellite above interface `k` (1-based), the body the spring pushes.
fn satellite_mass(m: &Model, interface: usize) -> f64 {
    m.satellites
        .get(interface.saturating_sub(1))
        .map_or(f64::INFINITY, |s| s.mass_kg)
}

/// 2π·√(m/k), s.
fn period(k: f64, mass: f64) -> f64 {
    2.0 * std::f64::consts::PI * (mass / k).sqrt()
}

/// Duration of one contact F = K·δⁿ at the impact speed, for a satellite of `mass`: the
/// penetration at rest is δ = ((n+1)·m·v²/(2K))^(1/(n+1)) (energy balance), and half a period
/// of the stiffness linearised there, n·K·δ^(n−1), approximates the contact time.
fn contact_period(m: &Model, mass: f64) -> f64 {
    let (k, n) = (m.contact.stiffness, m.contact.exponent);
    let v = IMPACT_SPEED_M_S;
    let depth = ((n + 1.0) * mass * v * v / (2.0 * k)).powf(1.0 / (n + 1.0));
    0.5 * period(n * k * depth.powf(n - 1.0), mass)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Linear contact (n = 1): the linearised stiffness is K itself, so the contact time is
    /// half the period π·√(m/K) exactly, whatever the speed.
    #[test]
    fn a_linear_contact_lasts_half_a_period() {
        let mut m = super::super::fixture::two_satellites();
        m.contact.stiffness = 1e6;
        m.contact.exponent = 1.0;
        let mass = 100.0;
        let want = std::f64::consts::PI * (mass / 1e6f64).sqrt();
        assert!((contact_period(&m, mass) - want).abs() < 1e-15 * want);
    }
}
