//! The stabilization diagram and the automatic choice of the physical poles.
//!
//! A pole of order n is compared with the pole of order n − 2 nearest in frequency. It is
//! *stable in frequency* when |Δf|/f < `df_rel`, *stable in damping* when, in addition,
//! |Δζ|/ζ < `dzeta_rel`, and *stable in vector* when, in addition, the MAC of the two pole
//! vectors is at least `mac_min`. Only physical poles enter the diagram: 0 < ζ < `zeta_max`,
//! frequency inside the band.
//!
//! Selection: the poles stable in vector are sorted by frequency and grouped, a new group
//! starting where the gap to the previous pole exceeds `df_rel`; a group is a mode when it
//! holds poles of at least `min_orders` distinct orders. The mode's pole is the group member of
//! median frequency (its own damping, so the pole stays one the estimator produced).

use super::indicators::mac;
use super::lscf::OrderFit;
use realfft::num_complex::Complex64;
use serde::Serialize;

/// Stability thresholds; the defaults are the customary ones of commercial PolyMAX
/// implementations (1 % frequency, 5 % damping, MAC 0.98).
#[derive(Debug, Clone, PartialEq)]
pub struct Criteria {
    pub df_rel: f64,
    pub dzeta_rel: f64,
    pub mac_min: f64,
    pub zeta_max: f64,
    pub min_orders: usize,
}

impl Default for Criteria {
    fn default() -> Self {
        Criteria {
            df_rel: 0.01,
            dzeta_rel: 0.05,
            mac_min: 0.98,
            zeta_max: 0.2,
            min_orders: 5,
        }
    }
}

/// The highest stability level a pole reached against the previous order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stability {
    New,
    Frequency,
    Damping,
    Vector,
}

/// One physical pole of the diagram.
#[derive(Debug, Clone)]
pub struct DiagramPole {
    pub order: usize,
    pub frequency_hz: f64,
    pub damping_ratio: f64,
    pub lambda: Complex64,
    pub vector: Vec<Complex64>,
    pub stability: Stability,
}

/// f (Hz) and ζ of a continuous-time pole λ = −ζω + jω√(1−ζ²).
pub fn frequency_damping(lambda: Complex64) -> (f64, f64) {
    let w = lambda.norm();
    (w / (2.0 * std::f64::consts::PI), -lambda.re / w)
}

/// The physical poles of every order, each marked against the previous order.
pub fn diagram(fits: &[OrderFit], band: (f64, f64), c: &Criteria) -> Vec<DiagramPole> {
    let mut out: Vec<DiagramPole> = Vec::new();
    let mut prev: Vec<DiagramPole> = Vec::new();
    for fit in fits {
        let mut cur = Vec::new();
        for (lambda, vector) in fit.poles.iter().zip(&fit.vectors) {
            let (f, z) = frequency_damping(*lambda);
            if !(z > 0.0 && z < c.zeta_max && f >= band.0 && f <= band.1) {
                continue;
            }
            let mut p = DiagramPole {
                order: fit.order,
                frequency_hz: f,
                damping_ratio: z,
                lambda: *lambda,
                vector: vector.clone(),
                stability: Stability::New,
            };
            p.stability = against(&p, &prev, c);
            cur.push(p);
        }
        out.extend(cur.iter().cloned());
        prev = cur;
    }
    out
}

fn against(p: &DiagramPole, prev: &[DiagramPole], c: &Criteria) -> Stability {
    let Some(q) = prev.iter().min_by(|a, b| {
        (a.frequency_hz - p.frequency_hz)
            .abs()
            .total_cmp(&(b.frequency_hz - p.frequency_hz).abs())
    }) else {
        return Stability::New;
    };
    if (p.frequency_hz - q.frequency_hz).abs() >= c.df_rel * q.frequency_hz {
        return Stability::New;
    }
    if (p.damping_ratio - q.damping_ratio).abs() >= c.dzeta_rel * q.damping_ratio {
        return Stability::Frequency;
    }
    if mac(&p.vector, &q.vector) < c.mac_min {
        return Stability::Damping;
    }
    Stability::Vector
}

/// A selected pole and the number of distinct orders at which its group was stable.
#[derive(Debug, Clone)]
pub struct Selected {
    pub pole: DiagramPole,
    pub stable_orders: usize,
}

/// The modes chosen from the diagram (see the module documentation), ascending in frequency.
pub fn select(diagram: &[DiagramPole], c: &Criteria) -> Vec<Selected> {
    let mut stable: Vec<&DiagramPole> = diagram
        .iter()
        .filter(|p| p.stability == Stability::Vector)
        .collect();
    stable.sort_by(|a, b| {
        a.frequency_hz
            .total_cmp(&b.frequency_hz)
            .then(a.order.cmp(&b.order))
    });
    let mut groups: Vec<Vec<&DiagramPole>> = Vec::new();
    for p in stable {
        match groups.last_mut() {
            Some(g) if p.frequency_hz - g[g.len() - 1].frequency_hz < c.df_rel * p.frequency_hz => {
                g.push(p)
            }
            _ => groups.push(vec![p]),
        }
    }
    groups
        .into_iter()
        .filter_map(|g| {
            let mut orders: Vec<usize> = g.iter().map(|p| p.order).collect();
            orders.sort_unstable();
            orders.dedup();
            (orders.len() >= c.min_orders).then(|| Selected {
                pole: g[(g.len() - 1) / 2].clone(),
                stable_orders: orders.len(),
            })
        })
        .collect()
}
