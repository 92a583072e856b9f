//! The release schedule: when the electromagnets let go, which springs start pushing, and
//! which bodies start moving. A body moves once it is latched to nothing: the interfaces
//! below and above it are released (the top satellite has none above; a fixed carrier never
//! moves). Bodies still latched to each other stay put until the interface between them is
//! released, even when the group is already cut from the carrier.

use super::super::params::Model;
use super::Sim;

/// The distinct release times before the end of the run, ascending.
pub(super) fn release_schedule(m: &Model) -> Vec<f64> {
    let mut releases: Vec<f64> = m
        .release_times_s
        .iter()
        .flatten()
        .copied()
        .filter(|&t| t < m.max_time_s)
        .collect();
    releases.sort_by(f64::total_cmp);
    releases.dedup();
    releases
}

impl Sim<'_> {
    /// Applies the releases due at time t: springs switch on, bodies whose latch chain to the
    /// fixed carrier is broken start moving.
    pub(super) fn apply_releases(&mut self, t: f64) {
        for k in 1..=self.n {
            if !self.released[k] && self.m.release_times_s[k - 1].is_some_and(|tk| tk <= t) {
                self.released[k] = true;
                for (si, s) in self.m.springs.iter().enumerate() {
                    if s.interface == k {
                        self.spring_on[si] = true;
                    }
                }
            }
        }
        // Groups of latched bodies; body n + 1 stands for the carrier (index 0).
        let n = self.n;
        let mut start = 1;
        while start <= n + 1 {
            let mut end = start;
            while end <= n && !self.released[end] {
                end += 1;
            }
            let has_carrier = end == n + 1;
            let single = end == start;
            let moving = single && !(has_carrier && self.m.carrier.is_none());
            if moving {
                self.free[if has_carrier { 0 } else { start }] = true;
            }
            start = end + 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    #[test]
    fn the_schedule_is_sorted_distinct_and_within_the_run() {
        let mut m = fixture::two_satellites();
        m.release_times_s = vec![Some(0.3), Some(0.1)];
        assert_eq!(release_schedule(&m), vec![0.1, 0.3]);
        m.release_times_s = vec![Some(0.2), Some(0.2)];
        assert_eq!(release_schedule(&m), vec![0.2]);
        m.release_times_s = vec![None, Some(m.max_time_s)];
        assert!(release_schedule(&m).is_empty());
    }

    /// Two satellites on a fixed carrier; interface k is below satellite k. Releasing
    /// interface 1 frees satellite 1 (nothing above it) and switches on its four springs,
    /// while satellite 2 stays latched to the carrier; releasing interface 2 frees it too.
    #[test]
    fn a_release_frees_the_bodies_cut_from_the_carrier() {
        let mut m = fixture::two_satellites();
        m.release_times_s = vec![Some(0.1), Some(0.2)];
        let mut sim = Sim::new(&m);
        sim.apply_releases(0.05);
        assert_eq!(sim.free, vec![false; 3]);
        sim.apply_releases(0.1);
        assert_eq!(sim.free, vec![false, true, false]);
        assert_eq!(sim.spring_on, [[true; 4], [false; 4]].concat());
        sim.apply_releases(0.2);
        assert_eq!(sim.free, vec![false, true, true]);
        assert!(sim.spring_on.iter().all(|&on| on));
    }

    /// Releasing only the lowest interface cuts the whole stack from the carrier, but the two
    /// satellites stay latched to each other: neither is free (only single bodies move).
    #[test]
    fn a_latched_pair_cut_from_the_carrier_stays_put() {
        let mut m = fixture::two_satellites();
        m.release_times_s = vec![None, Some(0.1)];
        let mut sim = Sim::new(&m);
        sim.apply_releases(0.1);
        assert_eq!(sim.free, vec![false; 3]);
        assert_eq!(sim.spring_on, [[false; 4], [true; 4]].concat());
    }
}
