//! The state vector's layout: 13 entries per body (body 0 = carrier, body i = satellite i:
//! position, quaternion w, x, y, z, velocity, body rates), then the bar modal coordinates
//! and their rates (4 bars × x, y × modes each), then three dissipation integrals (contact
//! damping, friction, bar damping). Here: the initial state, the absolute tolerances per
//! entry, and the name of the entry that went non-finite.

use super::super::body::{BODY_STATES, V3, v3_at};
use super::Sim;
use crate::error::SeparationError;
use std::ops::Range;

/// Velocity of body `b` in the state `y`, world axes.
#[inline]
pub(super) fn body_velocity(y: &[f64], b: usize) -> V3 {
    v3_at(y, BODY_STATES * b + 7)
}

/// Angular rate of body `b` in the state `y`, body axes.
#[inline]
pub(super) fn body_rate(y: &[f64], b: usize) -> V3 {
    v3_at(y, BODY_STATES * b + 10)
}

/// Whether every entry is finite, in one pass without an early exit (this runs twice per
/// step): x·0 is ±0 for a finite x and NaN otherwise, and four independent sums vectorise.
fn all_finite(y: &[f64]) -> bool {
    let mut acc = [0.0f64; 4];
    let chunks = y.chunks_exact(4);
    let mut rest = 0.0;
    for v in chunks.remainder() {
        rest += v * 0.0;
    }
    for c in chunks {
        for k in 0..4 {
            acc[k] += c[k] * 0.0;
        }
    }
    acc[0] + acc[1] + acc[2] + acc[3] + rest == 0.0
}

impl Sim<'_> {
    /// The entries that can change, as ascending ranges for the integrator's loops
    /// (`Dopri5::set_active`): the free bodies, the bar modes and the dissipation integrals.
    /// A body that does not move has a zero derivative (`rigid_body_rhs`).
    pub(super) fn active_ranges(&self) -> Vec<Range<usize>> {
        let mut ranges: Vec<Range<usize>> = Vec::new();
        let bodies = (0..=self.n).filter(|&b| self.free[b]);
        for r in bodies
            .map(|b| BODY_STATES * b..BODY_STATES * (b + 1))
            .chain(std::iter::once(self.bar_off..self.dim))
        {
            match ranges.last_mut() {
                Some(last) if last.end == r.start => last.end = r.end,
                _ => ranges.push(r),
            }
        }
        ranges
    }

    /// Every body at its latched position with the identity attitude; satellites given an
    /// initial velocity or rate (tests) start with it; bars straight and at rest.
    pub(super) fn initial_state(&self) -> Vec<f64> {
        let mut y = vec![0.0; self.dim];
        y[3] = 1.0;
        for (i, s) in self.m.satellites.iter().enumerate() {
            let o = BODY_STATES * (i + 1);
            let c = s.cg_offset_m;
            y[o] = c[0];
            y[o + 1] = c[1];
            y[o + 2] = s.bottom_z_m + 0.5 * self.m.pitch_m + c[2];
            y[o + 3] = 1.0;
            y[o + 7..o + 10].copy_from_slice(&s.initial_velocity_m_s);
            y[o + 10..o + 13].copy_from_slice(&s.initial_rate_rad_s);
        }
        y
    }

    /// Absolute tolerances: the relative tolerance times a physical scale per state kind
    /// (position 1 m, attitude 1, velocity 0.1 m/s, rate 0.01 rad/s, bar deflection 1 mm and
    /// deflection rate 1 mm/s in modal units, energies the scene's spring energy).
    pub(super) fn atol(&self, tol: f64) -> Vec<f64> {
        let mut a = vec![0.0; self.dim];
        for b in 0..=self.n {
            let o = BODY_STATES * b;
            a[o..o + 3].fill(tol);
            a[o + 3..o + 7].fill(tol);
            a[o + 7..o + 10].fill(tol * 0.1);
            a[o + 10..o + 13].fill(tol * 0.01);
        }
        if let Some(bar) = &self.m.bars {
            let modal_mass_scale = bar.shapes[0].eval(bar.length_m).0.abs().recip().max(1e-12);
            a[self.bar_off..self.en_off].fill(tol * 1e-3 * modal_mass_scale);
        }
        a[self.en_off..].fill(tol * self.e_ref);
        a
    }

    /// Index of the modal coordinate of `mode` of bar `bar` in direction `dir` (0 = x,
    /// 1 = y); its rate sits 8 × modes entries further.
    #[inline]
    pub(super) fn qidx(&self, bar: usize, dir: usize, mode: usize) -> usize {
        self.bar_off + (bar * 2 + dir) * self.nm + mode
    }

    /// The error naming the first non-finite entry of `y` (a state or a derivative) at `t`.
    pub(super) fn non_finite(&self, t: f64, y: &[f64]) -> Option<SeparationError> {
        if all_finite(y) {
            return None;
        }
        let bad = y.iter().position(|v| !v.is_finite())?;
        Some(SeparationError::NonFinite {
            time_s: t,
            body: self.entry_owner(bad),
        })
    }

    /// What state entry `index` belongs to, in words.
    fn entry_owner(&self, index: usize) -> String {
        if index < self.bar_off {
            let b = index / BODY_STATES;
            if b == 0 {
                "the carrier".to_string()
            } else {
                format!("satellite {b}")
            }
        } else if index < self.en_off {
            let r = index - self.bar_off;
            let r = r % (8 * self.nm);
            let bd = r / self.nm;
            format!(
                "guide bar {} ({}), mode {}",
                bd / 2 + 1,
                if bd.is_multiple_of(2) { "x" } else { "y" },
                r % self.nm + 1
            )
        } else {
            "the energy accumulators".to_string()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// Packing the initial velocity and rate into the state and reading them back gives
    /// them unchanged (copies, no arithmetic: exact).
    #[test]
    fn initial_velocity_and_rate_round_trip_through_the_state() {
        let mut m = fixture::two_satellites();
        m.satellites[1].initial_velocity_m_s = [0.1, -0.2, 0.3];
        m.satellites[1].initial_rate_rad_s = [0.01, 0.02, -0.03];
        let sim = Sim::new(&m);
        let y = sim.initial_state();
        assert_eq!(y.len(), 13 * 3 + 3);
        assert_eq!(body_velocity(&y, 2), V3::new(0.1, -0.2, 0.3));
        assert_eq!(body_rate(&y, 2), V3::new(0.01, 0.02, -0.03));
        assert_eq!(body_velocity(&y, 1), V3::zeros());
        // Satellite 2's CG: column-segment centre (bottom 0.2 + half pitch 0.25) + offset.
        assert_eq!(&y[26..30], &[0.01, -0.02, 0.2 + 0.25 + 0.03, 1.0]);
    }

    /// The modal coordinates tile the bar block exactly once (8 directions × modes), the
    /// rates fill the second half, and the energy integrals follow.
    #[test]
    fn modal_indices_cover_the_bar_block_once() {
        let m = fixture::two_satellites_on_flexible_bars(2);
        let sim = Sim::new(&m);
        let mut seen = vec![0; sim.dim];
        for bar in 0..4 {
            for dir in 0..2 {
                for mode in 0..2 {
                    let q = sim.qidx(bar, dir, mode);
                    seen[q] += 1;
                    seen[q + 8 * sim.nm] += 1;
                }
            }
        }
        assert!(seen[..sim.bar_off].iter().all(|&c| c == 0));
        assert!(seen[sim.bar_off..sim.en_off].iter().all(|&c| c == 1));
        assert_eq!(sim.dim - sim.en_off, 3);
    }

    /// Satellite 1 free, the carrier and satellite 2 latched: satellite 1's entries and the
    /// bar block with the integrals; satellite 2 freed too joins them into one range.
    #[test]
    fn active_ranges_are_the_free_bodies_and_the_bars() {
        let m = fixture::two_satellites_on_flexible_bars(2);
        let mut sim = Sim::new(&m);
        sim.free[1] = true;
        assert_eq!(sim.active_ranges(), vec![13..26, sim.bar_off..sim.dim]);
        sim.free[2] = true;
        assert_eq!(sim.active_ranges(), vec![13..sim.dim]);
    }

    #[test]
    fn a_non_finite_entry_is_named_by_its_owner() {
        let m = fixture::two_satellites_on_flexible_bars(2);
        let sim = Sim::new(&m);
        let name = |i: usize| {
            let mut y = vec![0.0; sim.dim];
            y[i] = f64::NAN;
            match sim.non_finite(0.5, &y) {
                Some(SeparationError::NonFinite { time_s, body }) => {
                    assert_eq!(time_s, 0.5);
                    body
                }
                other => panic!("expected NonFinite, got {other:?}"),
            }
        };
        assert_eq!(name(5), "the carrier");
        assert_eq!(name(13 + 2), "satellite 1");
        assert_eq!(name(sim.qidx(2, 1, 1)), "guide bar 3 (y), mode 2");
        assert_eq!(name(sim.qidx(0, 0, 0) + 16), "guide bar 1 (x), mode 1");
        assert_eq!(name(sim.en_off + 1), "the energy accumulators");
        assert!(sim.non_finite(0.0, &sim.initial_state()).is_none());
    }

    /// Any NaN or infinity, in the chunks or in the remainder, fails the one-pass test;
    /// finite values of any size and sign (−0 included) pass.
    #[test]
    fn the_one_pass_finiteness_test_finds_every_bad_entry() {
        let good = [1e308, -1e308, -0.0, 5e-324, 3.0, -2.5, 0.0];
        assert!(all_finite(&good));
        for i in 0..good.len() {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut y = good;
                y[i] = bad;
                assert!(!all_finite(&y), "{i}: {bad}");
            }
        }
    }
}
