//! Contact loads of the touching bore edges: the Lankarani–Nikravesh normal force along the
//! gradient of δ (lateral along the contact normal, axial from the bar slope), the
//! regularised Coulomb friction at the contact point on the bore, equal and opposite on the
//! carrier, and the generalised forces on the bar modes.

use super::super::body::V3;
use super::super::contact::ContactModel;
use super::Sim;
use super::edges::EdgeKin;
use super::forces::Loads;

impl Sim<'_> {
    /// Loads of every touching edge into `loads` and the generalised bar forces into `q_gen`;
    /// returns the power dissipated by contact damping and by friction.
    pub(super) fn contact_loads(
        &self,
        y: &[f64],
        loads: &mut Loads,
        q_gen: &mut [f64],
    ) -> (f64, f64) {
        let c = &self.m.contact;
        let (mut p_contact, mut p_fric) = (0.0, 0.0);
        let frames = loads.frames;
        let c0 = &frames[0];
        let len = self.m.bar_length_m;
        for &ei in &self.touching {
            let (i, j, k) = Self::edge_index(ei);
            let ec = &self.edges[ei];
            // Full kinematics at once: a listed edge almost always touches, so a δ-only
            // pre-screen would only compute δ twice more.
            let ek = self.edge_kin(y, c0, &frames[i], i, j, k, false);
            if ek.delta <= 0.0 || ek.z < 0.0 || ek.z > len {
                continue;
            }
            if c.model == ContactModel::Line && !self.edges[ei ^ 1].past_tip {
                let (pc, pf) = self.line_loads(y, ei, &ek, loads, q_gen);
                p_contact += pc;
                p_fric += pf;
                continue;
            }
            let v_imp = ec.impact_speed.unwrap_or(c.min_impact_speed);
            let (fnrm, fel) = c.normal_and_elastic(ek.delta, ek.delta_dot, v_imp);
            p_contact += (fnrm - fel) * ek.delta_dot;
            let n = ek.n;
            // −F·∇δ: lateral along n, axial from the bar slope.
            let f_loc = V3::new(
                fnrm * n[0],
                fnrm * n[1],
                -fnrm * (n[0] * ek.slope[0] + n[1] * ek.slope[1]),
            );
            let f_w = self.carrier_axes_to_world(c0, f_loc);
            loads.apply(i, f_w, ek.p);
            loads.apply(0, -f_w, ek.p);
            let mut bar_f = [-fnrm * n[0], -fnrm * n[1]];
            if c.friction > 0.0
                && let Some(p) = self.friction_load(&ek, i, fnrm, loads, &mut bar_f)
            {
                p_fric += p;
            }
            for mo in 0..self.nm {
                q_gen[(j * 2) * self.nm + mo] += bar_f[0] * ek.phi[mo];
                q_gen[(j * 2 + 1) * self.nm + mo] += bar_f[1] * ek.phi[mo];
            }
        }
        (p_contact, p_fric)
    }

    /// Friction of edge `ek` of satellite `i` under the normal force `fnrm`: applied at the
    /// contact point on the bore (one bore radius from the edge towards the bar) against the
    /// tangential sliding velocity relative to the deflecting bar; its reaction on the bar
    /// goes into `bar_f`. Returns the dissipated power, or `None` below the sticking speed
    /// (where the regularised friction vanishes).
    pub(super) fn friction_load(
        &self,
        ek: &EdgeKin,
        i: usize,
        fnrm: f64,
        loads: &mut Loads,
        bar_f: &mut [f64; 2],
    ) -> Option<f64> {
        let c = &self.m.contact;
        let frames = loads.frames;
        let (c0, s) = (&frames[0], &frames[i]);
        let n = ek.n;
        let br = self.m.bore_radius_m;
        let rc = self.carrier_axes_to_world(c0, V3::new(br * n[0], br * n[1], 0.0));
        let cpt = ek.p + rc;
        let vc = ek.vp + s.w.cross(&rc);
        let vr = self.velocity_in_carrier(c0, vc, cpt);
        let vr = V3::new(vr[0] - ek.udot[0], vr[1] - ek.udot[1], vr[2]);
        let vn = vr[0] * n[0] + vr[1] * n[1];
        let vt = V3::new(vr[0] - vn * n[0], vr[1] - vn * n[1], vr[2]);
        let vtm = vt.norm();
        let cd = c.friction_factor(vtm);
        // Not `cd <= 0.0`: a NaN sliding speed must apply no friction either.
        if cd > 0.0 {
            let ft = c.friction * cd * fnrm;
            let ft_loc = vt * (-ft / vtm);
            let ft_w = self.carrier_axes_to_world(c0, ft_loc);
            loads.apply(i, ft_w, cpt);
            loads.apply(0, -ft_w, cpt);
            bar_f[0] -= ft_loc[0];
            bar_f[1] -= ft_loc[1];
            Some(ft * vtm)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// Satellite 1 free, pushed 1.5 mm along +x (δ = 0.5 mm on every edge, normal −x) and
    /// sliding up at 0.3 m/s, all eight edges listed as touching at the floor impact speed:
    /// each edge carries the LN force K δ^1.5 (1 + 3(1 − Ce²) δ̇ / (4 v⁻)) with δ̇ = 0, pushing
    /// the satellite towards −x, and friction μ K δ^1.5 downwards (full Coulomb above v1).
    /// Reference: eq. 34 and eq. 36 by hand; tolerance: roundings.
    #[test]
    fn touching_edges_push_back_along_the_normal_with_coulomb_friction() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13] += 1.5e-3;
        y[13 + 9] = 0.3;
        sim.free[1] = true;
        sim.touching = (0..8).collect();
        let mut dy = vec![0.0; sim.dim];
        sim.rhs(&y, &mut dy);
        let f = 1e9 * 0.5e-3f64.powf(1.5);
        let (mass, mu) = (150.0, 0.1);
        assert!(
            (dy[13 + 7] - (-8.0 * f / mass)).abs() < 1e-9 * f,
            "{}",
            dy[20]
        );
        assert!(
            (dy[13 + 9] - (-8.0 * mu * f / mass)).abs() < 1e-9 * f,
            "{}",
            dy[22]
        );
        assert!(dy[13 + 8].abs() < 1e-9 * f);
        // Friction power: μ F |v_t| per edge; damping power zero at δ̇ = 0.
        assert_eq!(dy[sim.en_off], 0.0);
        let p = 8.0 * mu * f * 0.3;
        assert!(
            (dy[sim.en_off + 1] - p).abs() < 1e-12 * p,
            "{}",
            dy[sim.en_off + 1]
        );
    }
}
