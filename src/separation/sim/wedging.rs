//! Wedging and free-flight tracking. A satellite whose axial speed falls below the stall
//! speed while its bores are still on the bars, after it has moved, has stalled: the drawer
//! effect, where a tilted satellite pressed at diagonal bore edges is held by the friction
//! there. The stall is recorded with the edges that carried the load, and the satellite then
//! counts as finished for the end of the run. After the exits, the gap of consecutive
//! satellites is followed until they are `track_clearance_to_m` apart (or the time is up).

use super::super::body::BODY_STATES;
use super::super::integrator::Dopri5;
use super::Sim;
use super::layout::body_velocity;
use super::records::Records;
use super::results::{EdgeLoad, Stall};

impl Sim<'_> {
    /// Records the stalls at the step end and marks the stalled satellites.
    pub(super) fn watch_stalls(&mut self, ig: &Dopri5, rec: &mut Records) {
        let v_stall = self.m.stall_speed_m_s;
        let v_carrier = body_velocity(&ig.y, 0)[2];
        for i in 0..self.n {
            let engaged = self.free[i + 1] && self.exit[i].is_none() && !self.stalled[i];
            if !engaged || rec.max_speed[i] < 2.0 * v_stall {
                continue;
            }
            let v = body_velocity(&ig.y, i + 1)[2] - v_carrier;
            // The slowest speed is that of the coast, once its springs have stopped pushing
            // (before, it is the speed it is being accelerated through).
            if self.springs_done(i + 1) {
                let slowest = rec.min_engaged_speed[i].map_or(v, |m| m.min(v));
                rec.min_engaged_speed[i] = Some(slowest);
            }
            if v < v_stall {
                self.stalled[i] = true;
                rec.stall[i] = Some(self.stall(&ig.y, ig.t, i, v, rec.z0[i]));
            }
        }
    }

    /// The springs of interface `k` (below satellite k) are released and have all reached
    /// their end of action.
    fn springs_done(&self, k: usize) -> bool {
        self.released[k]
            && self
                .m
                .springs
                .iter()
                .zip(&self.spring_on)
                .all(|(s, &on)| s.interface != k || !on)
    }

    /// Satellite `i` (0-based) stalled at time `t` with axial speed `v`; `z0` is its latched
    /// CG height.
    fn stall(&self, y: &[f64], t: f64, i: usize, v: f64, z0: f64) -> Stall {
        let c = &self.m.contact;
        let mut loads: Vec<EdgeLoad> = self
            .touching
            .iter()
            .filter(|&&ei| ei / 8 == i)
            .filter_map(|&ei| {
                let (delta, delta_dot) = self.kin_of(y, ei);
                let v_imp = self.edges[ei].impact_speed.unwrap_or(c.min_impact_speed);
                let f = c.normal_force(delta, delta_dot, v_imp);
                let (_, column, end) = Self::edge_index(ei);
                (delta > 0.0 && f > 0.0).then_some(EdgeLoad {
                    column: column + 1,
                    edge: if end == 0 { "bottom" } else { "top" },
                    normal_force_n: f,
                })
            })
            .collect();
        loads.sort_by(|a, b| b.normal_force_n.total_cmp(&a.normal_force_n));
        let release = self.m.release_times_s[i].unwrap_or(0.0);
        Stall {
            time_s: t - release,
            travel_m: y[BODY_STATES * (i + 1) + 2] - z0,
            axial_speed_m_s: v,
            loads,
            friction: c.friction,
        }
    }

    /// Every pair of consecutive moving satellites (neither stalled) has been
    /// `track_clearance_to_m` apart.
    pub(super) fn pairs_apart(&self, rec: &Records) -> bool {
        self.m.track_clearance_to_m <= 0.0
            || (0..self.n.saturating_sub(1)).all(|k| {
                let tracked = self.free[k + 1] && self.free[k + 2];
                let stalled = self.stalled[k] || self.stalled[k + 1];
                !tracked || stalled || rec.apart_time[k].is_some()
            })
    }
}
