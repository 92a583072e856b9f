//! The single-degree-of-freedom filters of the shock response spectrum: Smallwood's
//! ramp-invariant recursive coefficients (D. O. Smallwood, "An improved recursive formula for
//! calculating shock response spectra", Shock and Vibration Bulletin 51, 1981; ISO 18431-4) and
//! one pass of a filter over a record followed by its residual (zero-input) tail.
//!
//! The coefficients were checked against endaq-python's `_absolute_acceleration_coefficients`
//! and `_pseudo_velocity_coefficients` (endaq.calc.shock), and against scipy's first-order-hold
//! (ramp-invariant) discretisation of the continuous transfer functions, by
//! `data/signal-refs/make_srs_refs.py`.

/// A second-order section y[k] = b0 x[k] + b1 x[k-1] + b2 x[k-2] - a1 y[k-1] - a2 y[k-2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Biquad {
    pub b: [f64; 3],
    /// a1, a2 (a0 = 1).
    pub a: [f64; 2],
}

/// The pole terms shared by every response: E = exp(-ζωT), K = ωd T, E cos K, E sin K.
struct Poles {
    e: f64,
    k: f64,
    c: f64,
    s: f64,
}

fn poles(f_hz: f64, q: f64, dt: f64) -> Poles {
    let w = 2.0 * std::f64::consts::PI * f_hz;
    let zeta = 1.0 / (2.0 * q);
    let e = (-zeta * w * dt).exp();
    let k = w * dt * (1.0 - zeta * zeta).sqrt();
    Poles {
        e,
        k,
        c: e * k.cos(),
        s: e * k.sin(),
    }
}

/// Absolute acceleration of the mass per unit base acceleration,
/// H(s) = (2ζωs + ω²)/(s² + 2ζωs + ω²).
pub fn absolute_acceleration(f_hz: f64, q: f64, dt: f64) -> Biquad {
    let p = poles(f_hz, q, dt);
    let sp = p.s / p.k;
    Biquad {
        b: [1.0 - sp, 2.0 * (sp - p.c), p.e * p.e - sp],
        a: [-2.0 * p.c, p.e * p.e],
    }
}

/// Pseudo-velocity ω·z per unit base acceleration, z the relative displacement
/// (z'' + 2ζωz' + ω²z = -y''), H(s) = -ω/(s² + 2ζωs + ω²). ISO 18431-4 form.
pub fn pseudo_velocity(f_hz: f64, q: f64, dt: f64) -> Biquad {
    let p = poles(f_hz, q, dt);
    let w = 2.0 * std::f64::consts::PI * f_hz;
    let e2 = p.e * p.e;
    // q' of the standard: (1/(2Q²) - 1)/sqrt(1 - 1/(4Q²)).
    let qq = (1.0 / (2.0 * q * q) - 1.0) / (1.0 - 1.0 / (4.0 * q * q)).sqrt();
    let wt = w * dt;
    let den = dt * w * w;
    Biquad {
        b: [
            ((1.0 - p.c) / q - qq * p.s - wt) / den,
            (2.0 * p.c * wt - (1.0 - e2) / q + 2.0 * qq * p.s) / den,
            (-e2 * (wt + 1.0 / q) + p.c / q - qq * p.s) / den,
        ],
        a: [-2.0 * p.c, e2],
    }
}

/// Largest and smallest response values over a stretch of samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extremes {
    pub max: f64,
    pub min: f64,
}

impl Extremes {
    const EMPTY: Extremes = Extremes {
        max: f64::NEG_INFINITY,
        min: f64::INFINITY,
    };

    fn add(&mut self, y: f64) {
        self.max = self.max.max(y);
        self.min = self.min.min(y);
    }

    /// The larger magnitude of the two (the maximax over this stretch).
    pub fn abs_max(&self) -> f64 {
        self.max.abs().max(self.min.abs())
    }
}

/// Filters `x` then `residual` zero samples, in the transposed direct form II that
/// `scipy.signal.lfilter` uses (so the two agree to rounding), and returns the extremes of the
/// response during the input (primary) and after it (residual). `x` must not be empty.
pub fn primary_residual(f: &Biquad, x: &[f64], residual: usize) -> (Extremes, Extremes) {
    let [b0, b1, b2] = f.b;
    let [a1, a2] = f.a;
    let (mut z1, mut z2) = (0.0, 0.0);
    let mut step = |xk: f64| {
        let y = b0 * xk + z1;
        z1 = b1 * xk - a1 * y + z2;
        z2 = b2 * xk - a2 * y;
        y
    };
    let mut primary = Extremes::EMPTY;
    for &xk in x {
        primary.add(step(xk));
    }
    let mut tail = Extremes::EMPTY;
    for _ in 0..residual {
        tail.add(step(0.0));
    }
    (primary, tail)
}
