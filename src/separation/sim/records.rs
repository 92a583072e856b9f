//! What a run keeps of its steps: per-satellite maxima (speed, acceleration, rate), the
//! smallest axial gap between neighbours, the largest energy residual, the sampled
//! histories; and the results assembled from them at the end.

use super::super::body::BODY_STATES;
use super::super::integrator::Dopri5;
use super::Sim;
use super::layout::{body_rate, body_velocity};
use super::results::RunOptions;
use super::results::{
    AccelHistory, History, PairClearance, SatelliteResult, SeparationResult, Stall,
};

/// Running records of one run.
pub(super) struct Records {
    pub(super) max_speed: Vec<f64>,
    max_acc: Vec<f64>,
    peak_rate: Vec<f64>,
    /// Smallest axial gap of each pair of neighbours while both are free, m.
    pair_min: Vec<f64>,
    /// When each pair's gap first reached `track_clearance_to_m`, and its latest gap.
    pub(super) apart_time: Vec<Option<f64>>,
    last_gap: Vec<f64>,
    /// Latched CG height of each satellite, m.
    pub(super) z0: Vec<f64>,
    /// Slowest axial speed on the bars after moving, and the stall (`wedging`).
    pub(super) min_engaged_speed: Vec<Option<f64>>,
    pub(super) stall: Vec<Option<Stall>>,
    max_rel_residual: f64,
    hist: Option<History>,
    accel: Option<AccelHistory>,
    /// Time of the next history sample, s.
    next_sample: f64,
    /// A state buffer for the dense output at the history samples.
    ybuf: Vec<f64>,
}

impl Records {
    pub(super) fn new(n: usize, opts: &RunOptions, dim: usize) -> Records {
        Records {
            max_speed: vec![0.0f64; n],
            max_acc: vec![0.0f64; n],
            peak_rate: vec![0.0f64; n],
            pair_min: vec![f64::INFINITY; n.saturating_sub(1)],
            apart_time: vec![None; n.saturating_sub(1)],
            last_gap: vec![0.0; n.saturating_sub(1)],
            z0: vec![0.0; n],
            min_engaged_speed: vec![None; n],
            stall: vec![None; n],
            max_rel_residual: 0.0f64,
            hist: opts.record_history.then(|| History {
                satellites: vec![Vec::new(); n],
                ..Default::default()
            }),
            accel: opts.record_acceleration.then(|| AccelHistory {
                times_s: Vec::new(),
                bodies: vec![Vec::new(); n + 1],
            }),
            next_sample: 0.0,
            ybuf: vec![0.0; dim],
        }
    }
}

impl Sim<'_> {
    /// History samples of the step just taken (possibly re-taken to an event).
    pub(super) fn sample_history(&self, ig: &Dopri5, rec: &mut Records) {
        if let Some(h) = rec.hist.as_mut() {
            while rec.next_sample <= ig.t + 1e-12 {
                ig.dense(rec.next_sample.min(ig.t), &mut rec.ybuf);
                self.record(h, rec.next_sample, &rec.ybuf);
                rec.next_sample += self.m.output_interval_s;
            }
        }
    }

    /// The acceleration of every body at the step end, from the derivative the integrator
    /// holds there (the forces at that state divided by the masses). Called once before the
    /// discrete changes of the step end and, when they changed a force, once after.
    pub(super) fn sample_acceleration(&self, ig: &Dopri5, rec: &mut Records) {
        if let Some(a) = rec.accel.as_mut() {
            let dy = ig.derivative();
            a.times_s.push(ig.t);
            for (b, samples) in a.bodies.iter_mut().enumerate() {
                samples.push(body_velocity(dy, b).into());
            }
        }
    }

    /// The maxima and gaps at the step end. The audit costs about one right-hand side:
    /// sample it every 8th step.
    pub(super) fn update_records(&self, ig: &Dopri5, rec: &mut Records) {
        let dyv = ig.derivative();
        for i in 0..self.n {
            if !self.free[i + 1] {
                continue;
            }
            let v = body_velocity(&ig.y, i + 1);
            let w = body_rate(&ig.y, i + 1);
            rec.max_speed[i] = rec.max_speed[i].max(v.norm());
            rec.max_acc[i] = rec.max_acc[i].max(body_velocity(dyv, i + 1).norm());
            rec.peak_rate[i] = rec.peak_rate[i].max(w.norm().to_degrees());
        }
        for k in 0..rec.pair_min.len() {
            if self.free[k + 1] && self.free[k + 2] {
                let gap = self.pair_gap(&ig.y, k + 1);
                rec.pair_min[k] = rec.pair_min[k].min(gap);
                rec.last_gap[k] = gap;
                if rec.apart_time[k].is_none() && gap >= self.m.track_clearance_to_m {
                    rec.apart_time[k] = Some(ig.t);
                }
            }
        }
        if ig.stats.steps.is_multiple_of(8) {
            let en = self.energy(&ig.y);
            rec.max_rel_residual = rec.max_rel_residual.max(en.relative_residual);
        }
    }

    /// Smallest axial gap between satellite `k`'s column bottoms and satellite k + 1's tops.
    fn pair_gap(&self, y: &[f64], k: usize) -> f64 {
        let (a, b) = (self.frame(y, k), self.frame(y, k + 1));
        (0..4)
            .map(|j| {
                let pa = a.x + a.r * self.column_ends[k - 1][j][0];
                let pb = b.x + b.r * self.column_ends[k][j][1];
                pa[2] - pb[2]
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// One history sample at time `t`, state `y`.
    fn record(&self, h: &mut History, t: f64, y: &[f64]) {
        h.times_s.push(t);
        for i in 0..self.n {
            let o = BODY_STATES * (i + 1);
            let v = body_velocity(y, i + 1);
            let w = body_rate(y, i + 1);
            h.satellites[i].push([
                y[o],
                y[o + 1],
                y[o + 2],
                v[0],
                v[1],
                v[2],
                v.norm(),
                w[0].to_degrees(),
                w[1].to_degrees(),
                w[2].to_degrees(),
                w.norm().to_degrees(),
            ]);
        }
        let e = self.energy(y);
        let losses =
            e.contact_damping_loss_j + e.friction_loss_j + e.bar_damping_loss_j + e.tip_cut_loss_j;
        h.energy.push([
            e.spring_work_j,
            e.kinetic_j,
            e.bar_j,
            e.contact_elastic_j,
            losses,
            e.residual_j,
        ]);
    }

    /// The results at the end of the run (integrator `ig`).
    pub(super) fn results(&self, ig: &Dopri5, rec: Records) -> SeparationResult {
        let y = &ig.y;
        let satellites = (0..self.n)
            .map(|i| self.satellite_result(ig, &rec, i))
            .collect();
        let mut energy = self.energy(y);
        energy.max_relative_residual = rec.max_rel_residual.max(energy.relative_residual);
        let pair_clearances: Vec<PairClearance> = (0..self.n.saturating_sub(1))
            .filter(|&k| rec.pair_min[k].is_finite())
            .map(|k| PairClearance {
                upper: k + 1,
                min_clearance_m: rec.pair_min[k],
                closing_speed_m_s: body_velocity(y, k + 2)[2] - body_velocity(y, k + 1)[2],
                apart_time_s: rec.apart_time[k],
                final_gap_m: rec.last_gap[k],
            })
            .collect();
        let min_clearance_m = pair_clearances
            .iter()
            .map(|p| p.min_clearance_m)
            .reduce(f64::min);
        let clearance_tracked_to_distance = self.pairs_apart(&rec);
        let mut result = SeparationResult {
            satellites,
            energy,
            transitions: self.transitions,
            stats: ig.stats,
            end_time_s: ig.t,
            pair_clearances,
            min_clearance_m,
            clearance_tracked_to_distance,
            history: rec.hist,
            acceleration: rec.accel,
            shock: None,
            warnings: Vec::new(),
        };
        result.warnings = result.find_warnings(self.m.stall_speed_m_s, self.m.max_time_s);
        result
    }

    /// Satellite `i` (0-based): at its exit from the bars, or at the end of the run.
    fn satellite_result(&self, ig: &Dopri5, rec: &Records, i: usize) -> SatelliteResult {
        let (t_exit, v, w) =
            self.exit[i].unwrap_or((ig.t, body_velocity(&ig.y, i + 1), body_rate(&ig.y, i + 1)));
        let rel = self.m.release_times_s[i];
        SatelliteResult {
            index: i + 1,
            release_time_s: rel,
            max_speed_m_s: rec.max_speed[i],
            max_accel_m_s2: rec.max_acc[i],
            peak_rate_deg_s: rec.peak_rate[i],
            final_speed_m_s: v.norm(),
            final_rate_deg_s: w.norm().to_degrees(),
            final_velocity_m_s: v.into(),
            final_rate_body_deg_s: (w * (180.0 / std::f64::consts::PI)).into(),
            exit_time_s: self.exit[i].map(|_| t_exit - rel.unwrap_or(0.0)),
            contacts: self.contacts[i],
            min_engaged_speed_m_s: rec.min_engaged_speed[i],
            stall: rec.stall[i].clone(),
            wedged: self.stalled[i] || (self.free[i + 1] && self.exit[i].is_none()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// Both satellites at their latched positions: satellite 1's column bottoms rest on
    /// satellite 2's tops (gap 0 up to the rounding of the heights); lifting satellite 1 by
    /// 2 cm opens the gap by 2 cm.
    #[test]
    fn the_pair_gap_is_the_axial_distance_of_the_column_ends() {
        let m = fixture::two_satellites();
        let sim = Sim::new(&m);
        let mut y = sim.initial_state();
        assert!(sim.pair_gap(&y, 1).abs() < 1e-15);
        y[13 + 2] += 0.02;
        assert!((sim.pair_gap(&y, 1) - 0.02).abs() < 1e-15);
    }

    /// A whole run of a free satellite coasting upwards at 0.2 m/s: it leaves the bars when
    /// its bottom edges pass the tip, (1.5 − 0.7) / 0.2 = 4 s after the start (by hand), at
    /// its initial speed; nothing acts on it, so its peak acceleration is zero.
    #[test]
    fn a_coasting_satellite_exits_at_the_closed_form_time() {
        let mut m = fixture::two_satellites();
        m.satellites[0].initial_velocity_m_s = [0.0, 0.0, 0.2];
        m.max_time_s = 10.0;
        let r = super::super::run(&m, &Default::default()).expect("the run completes");
        let s = &r.satellites[0];
        assert!(
            (s.exit_time_s.expect("it left") - 4.0).abs() < 1e-12,
            "{s:?}"
        );
        assert!((s.final_speed_m_s - 0.2).abs() < 1e-15);
        assert_eq!(s.max_accel_m_s2, 0.0);
        assert_eq!(r.satellites[1].exit_time_s, None);
    }
}
