//! The event functions and their crossings. Events, by index: [0, 8n) penetration δ of each
//! bore edge, [8n, 16n) height of each edge above the bar tip, [16n, 16n + 4n) extension of
//! each spring minus its end of action. An event is live only in the discrete state where its
//! crossing changes something (see [`Sim::crossed`]).

use super::super::body::BODY_STATES;
use super::super::contact::ContactState;
use super::Sim;
use super::frames::Frame;

impl Sim<'_> {
    pub(super) fn n_events(&self) -> usize {
        20 * self.n
    }

    /// Value of event `idx` at `y`, from the frames of every body at `y`.
    fn event_value(&self, y: &[f64], idx: usize, frames: &[Frame]) -> f64 {
        let n8 = 8 * self.n;
        if idx < 2 * n8 {
            let ei = idx % n8;
            let (i, j, k) = Self::edge_index(ei);
            let ek = self.edge_kin(y, &frames[0], &frames[i], i, j, k, false);
            if idx < n8 {
                ek.delta
            } else {
                ek.z - self.m.bar_length_m
            }
        } else {
            let si = idx - 2 * n8;
            self.spring_ext(frames, si).0 - self.m.springs[si].end_of_action_m()
        }
    }

    /// [`Self::event_value`] computing only the frames that event needs (root location
    /// evaluates one event many times).
    pub(super) fn event_value_at(&self, y: &[f64], idx: usize) -> f64 {
        let n8 = 8 * self.n;
        if idx < 2 * n8 {
            let ei = idx % n8;
            let (i, j, k) = Self::edge_index(ei);
            let ek = self.edge_kin(y, &self.frame(y, 0), &self.frame(y, i), i, j, k, false);
            if idx < n8 {
                ek.delta
            } else {
                ek.z - self.m.bar_length_m
            }
        } else {
            let si = idx - 2 * n8;
            self.spring_ext(&self.frames(y), si).0 - self.m.springs[si].end_of_action_m()
        }
    }

    /// The parts of the state that event `idx` reads: an edge event its carrier, its satellite
    /// and the bar modes; a spring event every body (it is rare: once per spring). Root
    /// location fills only these from the dense output.
    pub(super) fn event_state_parts(&self, idx: usize) -> [std::ops::Range<usize>; 3] {
        if idx < 16 * self.n {
            let b = BODY_STATES * ((idx % (8 * self.n)) / 8 + 1);
            [
                0..BODY_STATES,
                b..b + BODY_STATES,
                self.bar_off..self.en_off,
            ]
        } else {
            [0..self.dim, 0..0, 0..0]
        }
    }

    /// All event values into `g`, and the rate δ̇ of every edge's penetration into `gd` (for
    /// the hidden-contact test). Every edge is evaluated exactly (δ and δ̇), touching or not.
    pub(super) fn events(&self, y: &[f64], g: &mut [f64], gd: &mut [f64]) {
        // The right-hand side's frame buffer: the same frames `frames(y)` gives, without
        // an allocation per step.
        let mut sc = self.scratch.borrow_mut();
        self.update_frames(y, &mut sc.frames);
        let frames = &sc.frames;
        let n8 = 8 * self.n;
        for ei in 0..n8 {
            // `crossed`, the hidden-contact test and the state maintenance skip an edge past
            // the tip: its values are never read.
            if self.edges[ei].past_tip {
                continue;
            }
            let (delta, delta_dot, z) = self.edge_event(y, &frames[0], &frames[ei / 8 + 1], ei);
            g[ei] = delta;
            gd[ei] = delta_dot;
            g[n8 + ei] = z - self.m.bar_length_m;
        }
        for (idx, gi) in g.iter_mut().enumerate().skip(2 * n8) {
            *gi = self.event_value(y, idx, frames);
        }
    }

    /// Whether event `idx` is live and crossed between `a` (before) and `b` (after).
    #[inline(always)]
    pub(super) fn crossed(&self, idx: usize, a: f64, b: f64) -> bool {
        let n8 = 8 * self.n;
        if idx < n8 {
            let e = &self.edges[idx];
            if e.past_tip {
                return false;
            }
            let touching = matches!(e.state, ContactState::Collision | ContactState::Contact);
            // Onset of a free edge, or exit of a touching one; and the onset of an edge
            // switched on at δ < 0: the state after a re-taken step differs from the dense
            // output that located its onset by the step's local error, so an onset can land a
            // hair early, and the δ^1.5 corner it then crosses inside a step must be located
            // as well (it also re-latches the impact speed there).
            (!touching && a < 0.0 && b >= 0.0) || (touching && (a > 0.0) != (b > 0.0))
        } else if idx < 2 * n8 {
            let ei = idx - n8;
            !self.edges[ei].past_tip && self.free[ei / 8 + 1] && a < 0.0 && b >= 0.0
        } else {
            let si = idx - 2 * n8;
            self.released[self.m.springs[si].interface]
                && if self.spring_on[si] {
                    a < 0.0 && b >= 0.0
                } else {
                    a >= 0.0 && b < 0.0
                }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{self, SPRING_STROKE};
    use super::*;

    /// Satellite 1 lifted 5 cm with its interface released: the spring events read the
    /// extension minus the stroke (0.05 − 0.08, by hand), the tip events the edge heights
    /// minus the bar length, the δ events −c at the centred position; the full and the
    /// single-event evaluations agree bit for bit.
    #[test]
    fn event_values_read_extension_height_and_penetration() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13 + 2] += 0.05;
        sim.released[1] = true;
        let ne = sim.n_events();
        let (mut g, mut gd) = (vec![0.0; ne], vec![0.0; 16]);
        sim.events(&y, &mut g, &mut gd);
        for si in 0..4 {
            assert!(
                (g[32 + si] - (0.05 - SPRING_STROKE)).abs() < 1e-15,
                "{}",
                g[32 + si]
            );
        }
        // Satellite 1's top edges: bottom 0.7 + 0.05 + pitch 0.5, against the 1.5 m tip.
        assert!((g[16 + 1] - (1.25 - 1.5)).abs() < 1e-15, "{}", g[17]);
        assert!((g[0] + 1e-3).abs() < 1e-15);
        for (idx, &gi) in g.iter().enumerate() {
            assert_eq!(sim.event_value_at(&y, idx), gi, "event {idx}");
        }
    }

    /// Liveness: a free edge's onset counts only upwards through zero; a spring's end of
    /// action only once released, and switching back on only while off.
    #[test]
    fn crossings_count_only_for_live_events() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        assert!(sim.crossed(0, -1e-6, 1e-6));
        assert!(!sim.crossed(0, 1e-6, -1e-6));
        sim.edges[0].state = ContactState::Contact;
        assert!(sim.crossed(0, 1e-6, -1e-6));
        // Tip: only for a free satellite.
        assert!(!sim.crossed(16, -1e-3, 1e-3));
        sim.free[1] = true;
        assert!(sim.crossed(16, -1e-3, 1e-3));
        // Springs of interface 1: not before the release.
        assert!(!sim.crossed(32, -1e-3, 1e-3));
        sim.released[1] = true;
        sim.spring_on[0] = true;
        assert!(sim.crossed(32, -1e-3, 1e-3) && !sim.crossed(32, 1e-3, -1e-3));
        sim.spring_on[0] = false;
        assert!(sim.crossed(32, 1e-3, -1e-3) && !sim.crossed(32, -1e-3, 1e-3));
    }
}
