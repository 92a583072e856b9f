//! Bounded Levenberg–Marquardt (Marquardt 1963, with Nielsen's damping update, Madsen,
//! Nielsen & Tingleff, "Methods for non-linear least squares problems", 2004) for
//! min ½‖r(u)‖² + ½·ρ‖u − u₀‖² over box bounds. The bounds are kept by projection: a variable at
//! a bound that the gradient pushes outward is held there for the step.

use nalgebra::{DMatrix, DVector};

/// Stop when the step is below this, relative to ‖u‖.
pub const STEP_TOL: f64 = 1e-8;
/// Stop when the projected gradient of ½‖r‖² is below this (residuals are relative errors,
/// so 1e-10 is far below any frequency the model can be fitted to).
pub const GRAD_TOL: f64 = 1e-10;

/// Residuals and their Jacobian (rows: residuals, columns: variables) at one point.
pub struct Evaluation {
    pub r: DVector<f64>,
    pub j: DMatrix<f64>,
}

pub struct Options {
    pub max_iterations: usize,
    /// Tikhonov weight ρ toward `prior` (0: none).
    pub regularization: f64,
    pub prior: Vec<f64>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    Step,
    Gradient,
    MaxIterations,
}

pub struct Outcome {
    pub u: Vec<f64>,
    pub iterations: usize,
    pub stop: Stop,
}

/// Minimises from `start` (inside the bounds); `eval` gives r and J at a point.
pub fn minimize<E>(
    mut eval: impl FnMut(&[f64]) -> Result<Evaluation, E>,
    start: &[f64],
    o: &Options,
) -> Result<Outcome, E> {
    let mut u = start.to_vec();
    let mut at = eval(&u)?;
    let mut cost = cost_of(&at, &u, o);
    let mut mu = None;
    let mut nu = 2.0;
    for it in 1..=o.max_iterations {
        let (a, g) = normal_equations(&at, &u, o);
        let free = free_variables(&u, &g, o);
        let projected = (0..u.len()).filter(|&i| free[i]).map(|i| g[i].abs());
        if projected.fold(0.0, f64::max) < GRAD_TOL {
            return Ok(Outcome {
                u,
                iterations: it - 1,
                stop: Stop::Gradient,
            });
        }
        let damping = *mu.get_or_insert_with(|| 1e-3 * a.diagonal().max());
        let trial = step(&a, &g, &free, damping, &u, o);
        let size = trial
            .iter()
            .zip(&u)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt();
        let norm = u.iter().map(|x| x * x).sum::<f64>().sqrt();
        if size <= STEP_TOL * (norm + STEP_TOL) {
            return Ok(Outcome {
                u,
                iterations: it,
                stop: Stop::Step,
            });
        }
        let next = eval(&trial)?;
        let new_cost = cost_of(&next, &trial, o);
        if new_cost < cost {
            (u, at, cost) = (trial, next, new_cost);
            mu = Some(damping / 3.0);
            nu = 2.0;
        } else {
            mu = Some(damping * nu);
            nu *= 2.0;
        }
    }
    Ok(Outcome {
        u,
        iterations: o.max_iterations,
        stop: Stop::MaxIterations,
    })
}

/// ½‖r‖² + ½ρ‖u − u₀‖².
fn cost_of(e: &Evaluation, u: &[f64], o: &Options) -> f64 {
    let prior: f64 = u.iter().zip(&o.prior).map(|(x, p)| (x - p).powi(2)).sum();
    0.5 * e.r.norm_squared() + 0.5 * o.regularization * prior
}

/// JᵀJ + ρI and Jᵀr + ρ(u − u₀).
fn normal_equations(e: &Evaluation, u: &[f64], o: &Options) -> (DMatrix<f64>, DVector<f64>) {
    let n = u.len();
    let a = e.j.transpose() * &e.j + DMatrix::identity(n, n) * o.regularization;
    let prior = DVector::from_fn(n, |i, _| u[i] - o.prior[i]);
    let g = e.j.transpose() * &e.r + prior * o.regularization;
    (a, g)
}

/// Variables not held at a bound by a gradient pushing outward (the step goes along −g).
fn free_variables(u: &[f64], g: &DVector<f64>, o: &Options) -> Vec<bool> {
    (0..u.len())
        .map(|i| !((u[i] <= o.lower[i] && g[i] > 0.0) || (u[i] >= o.upper[i] && g[i] < 0.0)))
        .collect()
}

/// The damped Gauss–Newton step over the free variables (Marquardt's diagonal scaling, with
/// a floor so that a variable of no sensitivity still gets a finite step), clamped.
fn step(
    a: &DMatrix<f64>,
    g: &DVector<f64>,
    free: &[bool],
    mu: f64,
    u: &[f64],
    o: &Options,
) -> Vec<f64> {
    let n = u.len();
    let floor = 1e-12 * a.diagonal().max() + f64::MIN_POSITIVE;
    let mut lhs = a.clone();
    let mut rhs = -g.clone();
    for i in 0..n {
        if free[i] {
            lhs[(i, i)] += mu * a[(i, i)].max(floor);
        } else {
            for k in 0..n {
                lhs[(i, k)] = 0.0;
                lhs[(k, i)] = 0.0;
            }
            lhs[(i, i)] = 1.0;
            rhs[i] = 0.0;
        }
    }
    let delta = lhs
        .cholesky()
        .map(|c| c.solve(&rhs))
        .unwrap_or_else(|| DVector::zeros(n));
    (0..n)
        .map(|i| (u[i] + delta[i]).clamp(o.lower[i], o.upper[i]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock's function as least squares: r = (10(u₁ − u₀²), 1 − u₀) and its Jacobian.
    fn rosenbrock(u: &[f64]) -> Result<Evaluation, ()> {
        Ok(Evaluation {
            r: DVector::from_vec(vec![10.0 * (u[1] - u[0] * u[0]), 1.0 - u[0]]),
            j: DMatrix::from_row_slice(2, 2, &[-20.0 * u[0], 10.0, -1.0, 0.0]),
        })
    }

    /// Unregularised, 200 iterations, u₀ and u₁ in [−5, `upper`].
    fn box_options(upper: Vec<f64>) -> Options {
        Options {
            max_iterations: 200,
            regularization: 0.0,
            prior: vec![0.0; 2],
            lower: vec![-5.0; 2],
            upper,
        }
    }

    /// Rosenbrock as least squares, r = (10(u₁ − u₀²), 1 − u₀): minimum at (1, 1) (Rosenbrock
    /// 1960), reached to 1e-6 from the textbook start (−1.2, 1).
    #[test]
    fn rosenbrock_reaches_its_minimum() {
        let out = minimize(rosenbrock, &[-1.2, 1.0], &box_options(vec![5.0; 2])).unwrap();
        assert!(
            (out.u[0] - 1.0).abs() < 1e-6 && (out.u[1] - 1.0).abs() < 1e-6,
            "{:?}",
            out.u
        );
        assert_ne!(out.stop, Stop::MaxIterations);
    }

    /// The same with u₀ ≤ 0.5: the constrained minimum of (1 − u₀)² + 100(u₁ − u₀²)² is on the
    /// bound, u = (0.5, 0.25), exactly.
    #[test]
    fn a_bound_holds_the_variable() {
        let out = minimize(rosenbrock, &[-1.2, 1.0], &box_options(vec![0.5, 5.0])).unwrap();
        assert!(
            (out.u[0] - 0.5).abs() < 1e-9 && (out.u[1] - 0.25).abs() < 1e-6,
            "{:?}",
            out.u
        );
    }
}
