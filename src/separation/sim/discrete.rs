//! Discrete changes at an event point: a contact onset latches the impact speed (eq. 34), a
//! contact exit detaches the edge, an edge past the bar tip leaves the bar for good (a
//! pressed one takes its elastic energy with it), a spring switches at its end of action;
//! then the contact-state machine (eq. 38) of the edges without an event, and the list of
//! edges whose force the right-hand side evaluates.

use super::super::body::{BODY_STATES, v3_at};
use super::super::contact::{ContactModel, ContactState};
use super::Sim;

fn is_touching(state: ContactState) -> bool {
    matches!(state, ContactState::Collision | ContactState::Contact)
}

impl Sim<'_> {
    /// Applies the events `events_at_t` at time `t`, state `y`; `g0` holds the event values at
    /// the step start. Marks the edges they concern in `touched`.
    pub(super) fn apply_events(
        &mut self,
        y: &[f64],
        t: f64,
        g0: &[f64],
        events_at_t: &[usize],
        touched: &mut [bool],
    ) {
        let n8 = 8 * self.n;
        for &idx in events_at_t {
            if idx < n8 {
                touched[idx] = true;
                self.edge_crossing(y, idx, g0[idx]);
            } else if idx < 2 * n8 {
                let ei = idx - n8;
                touched[ei] = true;
                self.edge_past_tip(y, t, ei);
            } else {
                // A spring reaching its end of action switches off (one coming back within
                // it switches on); the step ends on the switch, and the FSAL refresh after
                // the discrete changes restarts after it.
                let si = idx - 2 * n8;
                self.spring_on[si] = !self.spring_on[si];
            }
        }
    }

    /// δ of edge `ei` crossed zero (it was `g0` at the step start): an onset latches the
    /// impact speed, an exit detaches, and a touching edge that was apart at the step start
    /// (an onset located a hair early) re-latches its impact speed.
    fn edge_crossing(&mut self, y: &[f64], ei: usize, g0: f64) {
        let min_impact = self.m.contact.min_impact_speed;
        let ek = self.kin_of(y, ei);
        let e = &mut self.edges[ei];
        let touching = is_touching(e.state);
        if touching && g0 <= 0.0 {
            e.impact_speed = Some(ek.1.max(min_impact));
        } else if touching {
            self.transitions.record(e.state, ContactState::Detached);
            e.state = ContactState::Detached;
            e.impact_speed = None;
        } else {
            self.transitions.record(e.state, ContactState::Collision);
            e.state = ContactState::Collision;
            e.impact_speed = Some(ek.1.max(min_impact));
            self.contacts[ei / 8] += 1;
        }
    }

    /// Edge `ei` passed the bar tip at time `t`: it leaves the bar (a pressed edge loses its
    /// contact's elastic energy), and the satellite's exit is recorded when it was its last.
    fn edge_past_tip(&mut self, y: &[f64], t: f64, ei: usize) {
        let (delta, _) = self.kin_of(y, ei);
        let line = self.m.contact.model == ContactModel::Line;
        // A line contact's bore loses its chord: its other edge falls back to the point law.
        if line && !self.edges[ei ^ 1].past_tip {
            let before = self.bore_elastic_energy(y, ei);
            self.edges[ei].past_tip = true;
            self.tip_cut_loss += before - self.bore_elastic_energy(y, ei);
        }
        let e = &mut self.edges[ei];
        e.past_tip = true;
        if is_touching(e.state) {
            if !line {
                self.tip_cut_loss += self.m.contact.elastic_energy(delta);
            }
            self.transitions.record(e.state, ContactState::Detached);
            e.state = ContactState::Detached;
            e.impact_speed = None;
        }
        let i = ei / 8;
        if self.exit[i].is_none() && self.edges[i * 8..i * 8 + 8].iter().all(|e| e.past_tip) {
            let o = BODY_STATES * (i + 1);
            self.exit[i] = Some((t, v3_at(y, o + 7), v3_at(y, o + 10)));
        }
    }

    /// Elastic energy of the edges of the bore of edge `ei` that have not left the bar (the
    /// edge at the tip included: its share is cut off there).
    fn bore_elastic_energy(&self, y: &[f64], ei: usize) -> f64 {
        let (i, j, _) = Self::edge_index(ei);
        let (c0, s) = (self.frame(y, 0), self.frame(y, i));
        (0..2)
            .filter(|&k| !self.edges[(ei & !1) + k].past_tip)
            .map(|k| {
                let ek = self.edge_kin(y, &c0, &s, i, j, k, false);
                self.edge_elastic_energy(y, (ei & !1) + k, ek)
            })
            .sum()
    }

    /// Contact-state maintenance at the step end (eq. 38) for the edges without an event;
    /// `g1` holds δ of every edge there (exact when near). Returns whether a force changed
    /// (an onset latched late, or a detachment).
    pub(super) fn maintain_contact_states(
        &mut self,
        y: &[f64],
        g1: &[f64],
        touched: &[bool],
    ) -> bool {
        let mut changed = false;
        for ei in 0..8 * self.n {
            if touched[ei] || self.edges[ei].past_tip {
                continue;
            }
            if let Some(s) = next_state(self.edges[ei].state, g1[ei] > 0.0) {
                changed |= self.switch_state(y, ei, s);
            }
        }
        changed
    }

    /// Moves edge `ei` to state `s` found by the maintenance; returns whether its force
    /// changed.
    fn switch_state(&mut self, y: &[f64], ei: usize, s: ContactState) -> bool {
        let ddot = if s == ContactState::Collision {
            self.kin_of(y, ei).1
        } else {
            0.0
        };
        let mut changed = false;
        let e = &mut self.edges[ei];
        self.transitions.record(e.state, s);
        if s == ContactState::Collision {
            // Missed onset (zero clearance, or a graze inside one step): latch now.
            self.transitions.late_onsets += 1;
            e.impact_speed = Some(ddot.max(self.m.contact.min_impact_speed));
            self.contacts[ei / 8] += 1;
            changed = true;
        }
        if s == ContactState::Detached {
            e.impact_speed = None;
            changed = true;
        }
        e.state = s;
        changed
    }

    /// The edges whose force the right-hand side evaluates from here on: those in collision
    /// or contact, and those sitting at δ ≥ 0 without a state (an edge that starts at the bar,
    /// as with zero clearance, has no crossing to locate: it touches from its first step, and
    /// the state maintenance latches it at that step's end). `g` holds δ of every edge now.
    pub(super) fn update_touching(&mut self, g: &[f64]) {
        self.touching.clear();
        for (ei, (e, &d)) in self.edges.iter().zip(g).enumerate() {
            if !e.past_tip && (d >= 0.0 || is_touching(e.state)) {
                self.touching.push(ei);
            }
        }
    }
}

/// The contact-state machine of eq. 38 at a step end without an event: the next state of an
/// edge in `state` with penetration `pressed` (δ > 0), or `None` when it stays.
fn next_state(state: ContactState, pressed: bool) -> Option<ContactState> {
    match (state, pressed) {
        (ContactState::Collision, true) => Some(ContactState::Contact),
        (ContactState::Collision, false) | (ContactState::Contact, false) => {
            Some(ContactState::Detached)
        }
        (ContactState::Detached, false) => Some(ContactState::Free),
        (ContactState::Detached, true) | (ContactState::Free, true) => {
            Some(ContactState::Collision)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::body::V3;
    use super::super::fixture;
    use super::*;
    use ContactState::*;

    /// Eq. 38 (paper §3.4): free → collision → contact → detached → free.
    #[test]
    fn the_state_machine_follows_eq_38() {
        assert_eq!(next_state(Free, true), Some(Collision));
        assert_eq!(next_state(Free, false), None);
        assert_eq!(next_state(Collision, true), Some(Contact));
        assert_eq!(next_state(Contact, true), None);
        assert_eq!(next_state(Contact, false), Some(Detached));
        assert_eq!(next_state(Detached, false), Some(Free));
        assert_eq!(next_state(Detached, true), Some(Collision));
    }

    /// Satellite 1 pushed 1.5 mm along +x (δ = 0.5 mm) and moving at 0.02 m/s along +x, so
    /// δ̇ = 0.02 m/s by hand: an onset event latches that impact speed and counts a contact;
    /// the exit event then detaches the edge.
    #[test]
    fn an_onset_latches_the_impact_speed_and_an_exit_detaches() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13] += 1.5e-3;
        y[13 + 7] = 0.02;
        let mut touched = vec![false; 16];
        sim.apply_events(&y, 0.1, &[-1e-6; 16], &[0], &mut touched);
        assert!(touched[0] && !touched[1]);
        assert_eq!(sim.edges[0].state, Collision);
        let v = sim.edges[0].impact_speed.expect("latched");
        assert!((v - 0.02).abs() < 1e-15, "{v}");
        assert_eq!(sim.contacts, vec![1, 0]);
        sim.apply_events(&y, 0.2, &[1e-6; 16], &[0], &mut touched);
        assert_eq!(sim.edges[0].state, Detached);
        assert_eq!(sim.edges[0].impact_speed, None);
    }

    /// The last edge of satellite 1 past the tip records its exit time, velocity and rate.
    #[test]
    fn the_last_edge_past_the_tip_records_the_exit() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13 + 7..13 + 13].copy_from_slice(&[0.0, 0.0, 0.3, 0.0, 0.0, 0.1]);
        let mut touched = vec![false; 16];
        let tips: Vec<usize> = (16..24).collect();
        sim.apply_events(&y, 1.0, &[0.0; 48], &tips[..7], &mut touched);
        assert_eq!(sim.exit[0], None);
        sim.apply_events(&y, 1.25, &[0.0; 48], &tips[7..], &mut touched);
        let exit = Some((1.25, V3::new(0.0, 0.0, 0.3), V3::new(0.0, 0.0, 0.1)));
        assert_eq!(sim.exit[0], exit);
        assert_eq!(sim.exit[1], None);
    }
}
