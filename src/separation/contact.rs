//! Bore-edge contact between a satellite column and a guide bar: the Lankarani–Nikravesh
//! normal force (paper eqs. 33–34), the regularised Coulomb friction (eqs. 36–37) and the
//! contact-state machine free → collision → contact → detached → free (eq. 38).
//!
//! Inputs: [`ContactParams`] built in `params` from `[separation.contact]`; the penetration δ
//! and its rate come from the geometry in `sim`. The impact speed δ̇⁻ of eq. 34 is latched by
//! `sim` at the located onset event and held in [`EdgeContact`]; it is never recomputed inside
//! integrator stages, which is what makes the LN restitution come out right.

pub use crate::spec::separation::ContactModel;
use serde::Serialize;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactParams {
    /// K, N/m^n.
    pub stiffness: f64,
    /// n.
    pub exponent: f64,
    /// Ce.
    pub restitution: f64,
    /// c_f.
    pub friction: f64,
    pub v0: f64,
    pub v1: f64,
    /// Floor of the latched impact speed, m/s.
    pub min_impact_speed: f64,
    /// Point (bore edges) or line (distributed along the overlap) contact.
    pub model: ContactModel,
    /// Line contact: force per unit length per unit penetration, N/m².
    pub line_stiffness: f64,
    /// Line contact: Gauss–Legendre points per edge share of the overlap.
    pub line_points: usize,
}

impl ContactParams {
    /// Normal force of eq. 34, F = K δⁿ [1 + 3(1 − Ce²) δ̇ / (4 δ̇⁻)], with δ̇⁻ the latched
    /// impact speed. Clamped at zero: a separating contact does not pull (the damping term can
    /// go below −Kδⁿ near the end of a low-Ce impact).
    #[inline]
    pub fn normal_force(&self, delta: f64, delta_dot: f64, impact_speed: f64) -> f64 {
        self.normal_and_elastic(delta, delta_dot, impact_speed).0
    }

    /// [`Self::normal_force`] and its elastic part K δⁿ, from one power (the right-hand side
    /// needs both for the damping power of the audit).
    #[inline]
    pub fn normal_and_elastic(&self, delta: f64, delta_dot: f64, impact_speed: f64) -> (f64, f64) {
        if delta <= 0.0 {
            return (0.0, 0.0);
        }
        // Hertz's 1.5 (the usual case) as δ·√δ: a square root costs a fraction of `powf`,
        // and this runs for every touching edge in every right-hand side.
        let dn = if self.exponent == 1.5 {
            delta * delta.sqrt()
        } else {
            delta.powf(self.exponent)
        };
        let kd = self.stiffness * dn;
        let damp = 3.0 * (1.0 - self.restitution * self.restitution) / (4.0 * impact_speed);
        ((kd * (1.0 + damp * delta_dot)).max(0.0), kd)
    }

    /// Elastic energy stored in the contact spring, ∫K δⁿ dδ.
    #[inline]
    pub fn elastic_energy(&self, delta: f64) -> f64 {
        if delta <= 0.0 {
            0.0
        } else {
            self.stiffness * delta.powf(self.exponent + 1.0) / (self.exponent + 1.0)
        }
    }

    /// The modified coefficient c_d of eq. 37 at sliding speed |v_t|.
    #[inline]
    pub fn friction_factor(&self, vt: f64) -> f64 {
        if vt <= self.v0 {
            0.0
        } else if vt >= self.v1 {
            1.0
        } else {
            (vt - self.v0) / (self.v1 - self.v0)
        }
    }
}

/// Relative motion state of one bore edge and its bar (paper §3.4, eq. 38).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactState {
    /// δ < 0 on both sides of the step.
    Free,
    /// The step in which δ changed sign from negative to positive (onset located).
    Collision,
    /// δ > 0 on both sides of the step.
    Contact,
    /// The step in which δ changed sign from positive to negative.
    Detached,
}

impl ContactState {
    pub fn index(self) -> usize {
        match self {
            ContactState::Free => 0,
            ContactState::Collision => 1,
            ContactState::Contact => 2,
            ContactState::Detached => 3,
        }
    }
}

/// Discrete state of one bore edge.
#[derive(Debug, Clone, Copy)]
pub struct EdgeContact {
    pub state: ContactState,
    /// δ̇⁻ latched at the onset; `None` while not in contact.
    pub impact_speed: Option<f64>,
    /// The edge has passed the bar tip: no more contact with this bar.
    pub past_tip: bool,
}

impl Default for EdgeContact {
    fn default() -> Self {
        EdgeContact {
            state: ContactState::Free,
            impact_speed: None,
            past_tip: false,
        }
    }
}

/// Counts of the four transitions of eq. 38 over all edges.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Transitions {
    pub free_to_collision: usize,
    pub collision_to_contact: usize,
    /// A collision that ends within its own onset step (a very short impact).
    pub collision_to_detached: usize,
    pub contact_to_detached: usize,
    pub detached_to_free: usize,
    /// A detached edge that is hit again before its next free step.
    pub detached_to_collision: usize,
    /// Onsets found at a step end rather than located as an event (δ ≥ 0 already at the
    /// start of a step: zero clearance, or a re-contact right after an exit). Their impact
    /// speed is latched at the step end, so they are the part of the run that depends on
    /// the step sequence.
    pub late_onsets: usize,
    /// Onsets found inside a step whose two ends both had δ < 0 (a pulse shorter than the
    /// step), located through the cubic interpolant of δ and the dense output.
    pub hidden_onsets: usize,
}

impl Transitions {
    pub fn record(&mut self, from: ContactState, to: ContactState) {
        use ContactState::*;
        match (from, to) {
            (Free, Collision) => self.free_to_collision += 1,
            (Collision, Contact) => self.collision_to_contact += 1,
            (Collision, Detached) => self.collision_to_detached += 1,
            (Contact, Detached) => self.contact_to_detached += 1,
            (Detached, Free) => self.detached_to_free += 1,
            (Detached, Collision) => self.detached_to_collision += 1,
            _ => {}
        }
    }

    pub fn add(&mut self, o: &Transitions) {
        self.free_to_collision += o.free_to_collision;
        self.collision_to_contact += o.collision_to_contact;
        self.collision_to_detached += o.collision_to_detached;
        self.contact_to_detached += o.contact_to_detached;
        self.detached_to_free += o.detached_to_free;
        self.detached_to_collision += o.detached_to_collision;
        self.late_onsets += o.late_onsets;
        self.hidden_onsets += o.hidden_onsets;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> ContactParams {
        ContactParams {
            stiffness: 1e9,
            exponent: 1.5,
            restitution: 0.8,
            friction: 0.2,
            v0: 1e-4,
            v1: 1e-2,
            min_impact_speed: 1e-4,
            model: ContactModel::Point,
            line_stiffness: 1e10,
            line_points: 4,
        }
    }

    #[test]
    fn ln_force_at_impact_speed_and_friction_ramp() {
        let c = p();
        // At δ̇ = δ̇⁻ the factor is 1 + 3(1 − 0.64)/4 = 1.27 (eq. 34).
        let f = c.normal_force(1e-6, 0.01, 0.01);
        assert!((f - 1e9 * 1e-9 * 1.27).abs() < 1e-12);
        assert_eq!(c.normal_force(-1e-6, 0.01, 0.01), 0.0);
        assert_eq!(c.friction_factor(5e-5), 0.0);
        assert!((c.friction_factor(0.00505) - 0.5).abs() < 1e-12);
        assert_eq!(c.friction_factor(1.0), 1.0);
    }
}
