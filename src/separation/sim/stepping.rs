//! The step loop of one run: start (initial state, releases due at t = 0, the integrator),
//! then per accepted step: integrate to at most the next release, locate and apply the
//! events, maintain the contact states, apply a release due now, restart the integrator after
//! a discrete change, and update the records; stop when every released satellite has left
//! the bars.

use super::super::body::BODY_STATES;
use super::super::integrator::{Dopri5, StepFailure};
use super::Sim;
use super::records::Records;
use super::releases::release_schedule;
use super::results::{RunOptions, SeparationResult};
use super::stiffness_scale::stiffest_element;
use crate::error::SeparationError;

/// The integrator and the event bookkeeping carried from one step to the next.
pub(super) struct Stepper {
    pub(super) ig: Dopri5,
    /// Distinct release times before the end of the run, ascending; the next one to apply.
    releases: Vec<f64>,
    next_release: usize,
    /// Event values at the start (`g0`) and end (`g1`) of the step, and δ̇ of every edge
    /// there (`gd0`, `gd1`, for the hidden-contact test).
    pub(super) g0: Vec<f64>,
    pub(super) g1: Vec<f64>,
    pub(super) gd0: Vec<f64>,
    pub(super) gd1: Vec<f64>,
    /// Events located in the current step, with their times.
    pub(super) located: Vec<(usize, f64)>,
    /// Edges that had an event at the current event point.
    touched: Vec<bool>,
    /// A state buffer for the dense output.
    pub(super) ybuf: Vec<f64>,
    /// The last step taken in contact, s (sizes the first step after an onset).
    h_contact: f64,
}

impl Stepper {
    fn release_pending(&self) -> bool {
        self.next_release < self.releases.len()
    }
}

impl Sim<'_> {
    pub(super) fn run(&mut self, opts: &RunOptions) -> Result<SeparationResult, SeparationError> {
        let mut st = self.start();
        let mut rec = Records::new(self.n, opts, self.dim);
        rec.z0 = (1..=self.n).map(|b| st.ig.y[BODY_STATES * b + 2]).collect();
        // The state at t = 0, after the releases due then (a release at t = 0 starts the
        // acceleration history with its spring force).
        self.sample_acceleration(&st.ig, &mut rec);
        while !self.finished(&st, &rec) {
            self.advance(&mut st)?;
            let events_at_t = self.resolve_events(&mut st)?;
            self.sample_history(&st.ig, &mut rec);
            self.sample_acceleration(&st.ig, &mut rec);
            let changed = self.apply_discrete_changes(&mut st, &events_at_t);
            self.restart(&mut st, changed, &events_at_t);
            if changed {
                self.sample_acceleration(&st.ig, &mut rec);
            }
            self.update_records(&st.ig, &mut rec);
            self.watch_stalls(&st.ig, &mut rec);
        }
        Ok(self.results(&st.ig, rec))
    }

    /// The initial state with the releases due at t = 0 applied, the integrator started on
    /// it, and the event values there.
    pub(super) fn start(&mut self) -> Stepper {
        let m = self.m;
        let n8 = 8 * self.n;
        let y0 = self.initial_state();
        // Bodies given an initial velocity (tests) move from the start, as if released.
        for (i, s) in m.satellites.iter().enumerate() {
            if s.initial_velocity_m_s != [0.0; 3] || s.initial_rate_rad_s != [0.0; 3] {
                self.free[i + 1] = true;
            }
        }
        let atol = self.atol(m.tolerance);
        let releases = release_schedule(m);
        // Releases due at t = 0 apply before the first step.
        let mut next_release = 0;
        while next_release < releases.len() && releases[next_release] <= 0.0 {
            self.apply_releases(0.0);
            next_release += 1;
        }
        self.rebuild_static(&y0);
        let ig = {
            let this = &*self;
            let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
            let mut ig = Dopri5::new(&mut f, 0.0, y0, m.tolerance, atol, m.max_step_s);
            ig.set_active(this.active_ranges());
            ig
        };
        let ne = self.n_events();
        let mut g0 = vec![0.0; ne];
        let mut gd0 = vec![0.0; n8];
        self.events(&ig.y, &mut g0, &mut gd0);
        self.update_touching(&g0[..n8]);
        Stepper {
            ig,
            releases,
            next_release,
            g0,
            g1: vec![0.0; ne],
            gd0,
            gd1: vec![0.0; n8],
            located: Vec::new(),
            touched: vec![false; n8],
            ybuf: vec![0.0; self.dim],
            h_contact: f64::INFINITY,
        }
    }

    /// Every released satellite has left the bars (or stalled on them), no release is
    /// pending and consecutive satellites are far enough apart; or the time is up.
    fn finished(&self, st: &Stepper, rec: &Records) -> bool {
        let released_any = self.released.iter().any(|&r| r);
        let all_out = (1..=self.n)
            .filter(|&i| self.free[i])
            .all(|i| self.exit[i - 1].is_some() || self.stalled[i - 1]);
        let done = released_any && all_out && !st.release_pending() && self.pairs_apart(rec);
        done || st.ig.t >= self.m.max_time_s
    }

    /// One accepted step, to at most the next release; errors on the step budget, a failed
    /// step or a non-finite state.
    fn advance(&self, st: &mut Stepper) -> Result<(), SeparationError> {
        let m = self.m;
        if st.ig.stats.steps >= m.max_steps {
            return Err(SeparationError::TooManySteps {
                time_s: st.ig.t,
                max_steps: m.max_steps,
                cause: stiffest_element(m),
            });
        }
        // A non-finite derivative at an accepted state (e.g. a zero inertia under a torque)
        // stops the run here, before any step spreads it.
        if let Some(e) = self.non_finite(st.ig.t, st.ig.derivative()) {
            return Err(e);
        }
        let t_limit = if st.release_pending() {
            st.releases[st.next_release]
        } else {
            m.max_time_s
        };
        let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| self.rhs(y, dy);
        st.ig
            .step(&mut f, t_limit)
            .map_err(|e| self.step_error(e))?;
        if let Some(e) = self.non_finite(st.ig.t, &st.ig.y) {
            return Err(e);
        }
        // The scale of the next onset's first step (see `restart`).
        if !self.touching.is_empty() {
            st.h_contact = st.ig.t - st.ig.t_prev();
        }
        Ok(())
    }

    /// The run's error for a failed step.
    fn step_error(&self, e: StepFailure) -> SeparationError {
        match e {
            StepFailure::TooSmall { t, h } => SeparationError::StepTooSmall {
                time_s: t,
                step_s: h,
                cause: stiffest_element(self.m),
            },
            StepFailure::NonFinite { t, index } => {
                let mut probe = vec![0.0; self.dim];
                probe[index] = f64::NAN;
                self.non_finite(t, &probe).expect("a NaN was placed")
            }
        }
    }

    /// The discrete changes at the step end: the events there, the contact-state maintenance,
    /// and a release due now. Returns whether anything changed that the right-hand side sees.
    fn apply_discrete_changes(&mut self, st: &mut Stepper, events_at_t: &[usize]) -> bool {
        let t = st.ig.t;
        st.touched.fill(false);
        let mut changed = !events_at_t.is_empty();
        self.apply_events(&st.ig.y, t, &st.g0, events_at_t, &mut st.touched);
        changed |= self.maintain_contact_states(&st.ig.y, &st.g1, &st.touched);
        if st.release_pending() && t >= st.releases[st.next_release] {
            self.apply_releases(t);
            self.rebuild_static(&st.ig.y);
            st.ig.set_active(self.active_ranges());
            st.next_release += 1;
            changed = true;
        }
        changed
    }

    /// After the discrete changes: the touching list, and on a change the FSAL stage (and
    /// the first step after an onset); the step end becomes the next step's start.
    fn restart(&mut self, st: &mut Stepper, changed: bool, events_at_t: &[usize]) {
        let n8 = 8 * self.n;
        self.update_touching(&st.g1[..n8]);
        if changed {
            // A step that starts on an onset starts on the δ^1.5 corner of the force,
            // where the embedded estimate of DOPRI5 misjudges the error: for a force
            // growing as t^1.5 from the step start the velocity error is 11.3× the
            // estimate (the quadrature error of t^1.5 under the tableau's weights against
            // that of its embedded pair). Its size comes from the pulses before it: half
            // the last step taken in contact, which the controller sized on a pulse.
            if st.h_contact.is_finite() && events_at_t.iter().any(|&i| i < n8 && st.g0[i] < 0.0) {
                st.ig.limit_next_step(0.5 * st.h_contact);
            }
            let this = &*self;
            let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
            st.ig.refresh(&mut f);
        }
        // Event values depend on the continuous state only: the discrete changes above
        // leave them as they are.
        // Swapped, not copied: `events` rewrites every value that is read before the next
        // step's values are (an edge past the tip keeps a stale one, which nothing reads).
        std::mem::swap(&mut st.g0, &mut st.g1);
        std::mem::swap(&mut st.gd0, &mut st.gd1);
    }
}
