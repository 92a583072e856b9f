//! The energy audit: the work the released springs have done against the kinetic energy of
//! the free bodies, the bars' modal energy, the contacts' elastic energy and the integrated
//! losses (contact damping, friction, bar damping, contacts cut at the bar tip). Their
//! difference, the residual, measures the integration error.

use super::super::body::{BODY_STATES, v3_at};
use super::super::contact::ContactModel;
use super::Sim;
use super::edges::EdgeKin;
use super::frames::Frame;
use super::results::EnergyAudit;

impl Sim<'_> {
    pub(super) fn energy(&self, y: &[f64]) -> EnergyAudit {
        let mut e = EnergyAudit::default();
        let frames = self.frames(y);
        for (si, s) in self.m.springs.iter().enumerate() {
            if self.released[s.interface] {
                e.spring_work_j += s.work(self.spring_ext(&frames, si).0);
            }
        }
        e.kinetic_j = self.kinetic_energy(y);
        e.bar_j = self.bar_energy(y);
        e.contact_elastic_j = self.contact_elastic_energy(y, &frames);
        e.contact_damping_loss_j = y[self.en_off];
        e.friction_loss_j = y[self.en_off + 1];
        e.bar_damping_loss_j = y[self.en_off + 2];
        e.tip_cut_loss_j = self.tip_cut_loss;
        e.residual_j = e.spring_work_j
            - (e.kinetic_j
                + e.bar_j
                + e.contact_elastic_j
                + e.contact_damping_loss_j
                + e.friction_loss_j
                + e.bar_damping_loss_j
                + e.tip_cut_loss_j);
        e.relative_residual = e.residual_j.abs() / self.e_ref;
        e
    }

    /// ½ m v² + ½ Σ I ω² of the free bodies (principal body axes).
    fn kinetic_energy(&self, y: &[f64]) -> f64 {
        let mut kinetic = 0.0;
        for b in 0..=self.n {
            if !self.free[b] {
                continue;
            }
            let (mass, inertia) = self.mass_properties(b);
            let o = BODY_STATES * b;
            let v = v3_at(y, o + 7);
            kinetic += 0.5 * mass * v.dot(&v);
            for a in 0..3 {
                kinetic += 0.5 * inertia[a] * y[o + 10 + a].powi(2);
            }
        }
        kinetic
    }

    /// ½ q̇² + ½ ω² q² of every bar mode (unit modal mass).
    fn bar_energy(&self, y: &[f64]) -> f64 {
        let mut bar_j = 0.0;
        if let Some(bar) = &self.m.bars {
            let nq = 8 * self.nm;
            for bd in 0..8 {
                for mo in 0..self.nm {
                    let qi = self.bar_off + bd * self.nm + mo;
                    bar_j += 0.5 * y[qi + nq].powi(2) + 0.5 * (bar.omega[mo] * y[qi]).powi(2);
                }
            }
        }
        bar_j
    }

    /// ∫ K δⁿ dδ of every pressed edge still on its bar.
    fn contact_elastic_energy(&self, y: &[f64], frames: &[Frame]) -> f64 {
        let mut elastic = 0.0;
        for i in 1..=self.n {
            for j in 0..4 {
                for k in 0..2 {
                    if self.edges[(i - 1) * 8 + j * 2 + k].past_tip {
                        continue;
                    }
                    let ek = self.edge_kin(y, &frames[0], &frames[i], i, j, k, true);
                    if ek.z >= 0.0 && ek.z <= self.m.bar_length_m {
                        elastic += self.edge_elastic_energy(y, (i - 1) * 8 + j * 2 + k, ek);
                    }
                }
            }
        }
        elastic
    }
}

impl Sim<'_> {
    /// Elastic energy of the contact of edge `ei` with penetration `ek.delta` (only δ is
    /// known when it does not touch): the point law's, or its share of a line contact while
    /// the other edge of its bore is on the bar.
    pub(super) fn edge_elastic_energy(&self, y: &[f64], ei: usize, ek: EdgeKin) -> f64 {
        if ek.delta <= 0.0 {
            return 0.0;
        }
        if self.m.contact.model == ContactModel::Line && !self.edges[ei ^ 1].past_tip {
            let (i, j, k) = Self::edge_index(ei);
            let ek = self.edge_kin(y, &self.frame(y, 0), &self.frame(y, i), i, j, k, false);
            return self.line_elastic_energy(y, ei, &ek);
        }
        self.m.contact.elastic_energy(ek.delta)
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{self, SPRING_K, SPRING_STROKE};
    use super::*;

    /// A free body moving at v = (0.1, −0.2, 0.3) m/s and turning at ω = (0.1, 0.2, −0.3)
    /// rad/s, nothing released: kinetic energy ½ m |v|² + ½ Σ I ω² by hand, no spring work, so
    /// the residual is minus the kinetic energy. Tolerance: roundings.
    #[test]
    fn the_audit_of_a_free_body_is_its_kinetic_energy() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13 + 7..13 + 13].copy_from_slice(&[0.1, -0.2, 0.3, 0.1, 0.2, -0.3]);
        sim.free[1] = true;
        let e = sim.energy(&y);
        let kinetic =
            0.5 * 150.0 * (0.01 + 0.04 + 0.09) + 0.5 * (16.0 * 0.01 + 22.0 * 0.04 + 30.0 * 0.09);
        assert!(
            (e.kinetic_j - kinetic).abs() < 1e-14 * kinetic,
            "{}",
            e.kinetic_j
        );
        assert_eq!(e.spring_work_j, 0.0);
        assert_eq!(e.contact_elastic_j, 0.0);
        assert_eq!(e.residual_j, -e.kinetic_j);
        // Normalised by the fixture's total spring energy: 8 springs × ½ k s².
        let e_ref = 8.0 * 0.5 * SPRING_K * SPRING_STROKE * SPRING_STROKE;
        assert!((e.relative_residual - kinetic / e_ref).abs() < 1e-14);
    }

    /// A released interface whose satellite rose 3 cm: each of its four springs did
    /// ½ k (s² − (s − 0.03)²) of work, by hand.
    #[test]
    fn released_springs_count_the_work_they_did() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13 + 2] += 0.03;
        sim.released[1] = true;
        let e = sim.energy(&y);
        let s = SPRING_STROKE;
        let work = 4.0 * 0.5 * SPRING_K * (s * s - (s - 0.03) * (s - 0.03));
        assert!(
            (e.spring_work_j - work).abs() < 1e-12 * work,
            "{}",
            e.spring_work_j
        );
    }
}
