//! Caches of the bodies that do not move (latched satellites, a fixed carrier): their frames,
//! the rigid-body kinematics of their edges and the lower seats of the springs on them. A body
//! that is not free has a zero derivative, so its state stays bit-for-bit what it was when the
//! cache was built, and the cache changes no bit of the results.

use super::super::body::{M3, V3};
use super::Sim;

impl Sim<'_> {
    /// Rebuilds the caches of the bodies that do not move, after a change of `free`.
    pub(super) fn rebuild_static(&mut self, y: &[f64]) {
        self.scratch.get_mut().frames.clear();
        self.carrier_at_rest = false;
        for b in 0..=self.n {
            self.static_frames[b] = None;
        }
        for e in self.static_edges.iter_mut() {
            *e = None;
        }
        self.static_spring_low.fill(None);
        if self.free[0] {
            return;
        }
        let mut frames = vec![None; self.n + 1];
        for (b, f) in frames.iter_mut().enumerate() {
            if !self.free[b] {
                *f = Some(self.frame_of(y, b));
            }
        }
        let c0 = frames[0].expect("the carrier is fixed");
        self.carrier_at_rest = c0.r == M3::identity()
            && c0.x == V3::zeros()
            && c0.v == V3::zeros()
            && c0.w == V3::zeros();
        for i in 1..=self.n {
            let Some(s) = frames[i] else { continue };
            for j in 0..4 {
                for k in 0..2 {
                    let (rb, p, pl) = self.edge_point(&c0, &s, i, j, k);
                    self.static_edges[(i - 1) * 8 + j * 2 + k] =
                        Some(self.edge_rigid(&c0, &s, rb, p, pl));
                }
            }
        }
        for (si, s) in self.m.springs.iter().enumerate() {
            if let Some(low) = frames[self.lower_body(s.interface)] {
                self.static_spring_low[si] = Some(low.x + low.r * self.spring_low[si]);
            }
        }
        self.static_frames = frames;
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// With satellite 1 free and moved, satellite 2 latched: the cached kinematics of the
    /// latched edges equal the uncached ones bit for bit (same formulas from the same state),
    /// the free satellite is not cached, and the fixed carrier at the origin is at rest.
    #[test]
    fn the_cache_of_latched_bodies_changes_no_bit() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13 + 7] = 0.2;
        y[26] += 1.2e-3;
        sim.free[1] = true;
        let uncached: Vec<(f64, f64)> = (0..16).map(|ei| sim.kin_of(&y, ei)).collect();
        sim.rebuild_static(&y);
        assert!(sim.carrier_at_rest);
        assert!(sim.static_frames[1].is_none() && sim.static_frames[2].is_some());
        assert!(sim.static_edges[..8].iter().all(Option::is_none));
        assert!(sim.static_edges[8..].iter().all(Option::is_some));
        let cached: Vec<(f64, f64)> = (0..16).map(|ei| sim.kin_of(&y, ei)).collect();
        assert_eq!(cached, uncached);
        // Satellite 2 moved 1.2 mm: its edges touch by 0.2 mm.
        assert!((cached[8].0 - 0.2e-3).abs() < 1e-15);
    }
}
