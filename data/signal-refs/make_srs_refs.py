"""Reference shock response spectra for tests/signal_srs.rs, computed independently of satqual.

Regenerate (from the repository root):
    python3 data/signal-refs/make_srs_refs.py
Needs numpy, scipy and endaq (pip install scipy endaq); runs offline.

1. The coefficients: Smallwood's ramp-invariant absolute-acceleration and ISO 18431-4
   pseudo-velocity coefficients, written out here, are first checked against scipy's
   first-order-hold (ramp-invariant) discretisation of the continuous transfer functions
   H_acc(s) = (2 zeta w s + w^2)/(s^2 + 2 zeta w s + w^2) and H_pv(s) = -w/(s^2 + 2 zeta w s + w^2),
   and against endaq's own coefficient functions.
2. Per natural frequency, scipy.signal.lfilter over the record and then over one damped period
   of the lowest frequency in zeros (int(T // dt) + 1 samples, T = 1/(fmin sqrt(1 - zeta^2))),
   continuing the filter state: primary = max|y| over the record, residual = over the zeros,
   positive = max y, negative = -min y over both, maximax, pseudo-velocity maximax (in the
   record's unit times seconds).
3. For the third-party record, endaq.calc.shock.shock_spectrum(two_sided=True, max_time=None)
   on the same frequencies: its neg/pos spectra.

Cases: `synthetic` (a half-sine plus a decaying sinusoid plus seeded noise, fs 20 kHz, Q = 10,
mean removed; the samples are stored in the JSON) and `hrshm` (data/realdata/hrshm-pcb-shock,
Q = 10, no offset removal).
"""
import json
import numpy as np
import scipy
import scipy.signal as sig
import endaq
import endaq.calc.shock as shock
import pandas as pd

root = __file__.rsplit("/data/", 1)[0]


def coeffs_acc(f, q, dt):
    w = 2 * np.pi * f
    z = 1 / (2 * q)
    e = np.exp(-z * w * dt)
    k = w * dt * np.sqrt(1 - z * z)
    c, s = e * np.cos(k), e * np.sin(k)
    sp = s / k
    return np.array([1 - sp, 2 * (sp - c), e * e - sp]), np.array([1, -2 * c, e * e])


def coeffs_pv(f, q, dt):
    w = 2 * np.pi * f
    z = 1 / (2 * q)
    e = np.exp(-z * w * dt)
    k = w * dt * np.sqrt(1 - z * z)
    c, s = e * np.cos(k), e * np.sin(k)
    qq = (1 / (2 * q * q) - 1) / np.sqrt(1 - 1 / (4 * q * q))
    wt, den = w * dt, dt * w * w
    b = np.array([((1 - c) / q - qq * s - wt) / den,
                  (2 * c * wt - (1 - e * e) / q + 2 * qq * s) / den,
                  (-e * e * (wt + 1 / q) + c / q - qq * s) / den])
    return b, np.array([1, -2 * c, e * e])


def check_coefficients(f, q, dt):
    """Largest relative difference of our coefficients from scipy FOH and from endaq."""
    w, z = 2 * np.pi * f, 1 / (2 * q)
    worst = 0.0
    for mine, num, theirs in [(coeffs_acc, [2 * z * w, w * w], shock._absolute_acceleration_coefficients),
                              (coeffs_pv, [-w], shock._pseudo_velocity_coefficients)]:
        b, a = mine(f, q, dt)
        bd, ad, _ = sig.cont2discrete((num, [1, 2 * z * w, w * w]), dt, method="foh")
        bd = np.ravel(bd)[-3:]
        be, ae = theirs(w, q, dt)
        for x, y in [(b, bd), (a, ad), (b, np.array(be)), (a, np.array(ae))]:
            worst = max(worst, float(np.max(np.abs(x - y)) / np.max(np.abs(y))))
    return worst


def spectrum(x, fs, freqs, q):
    dt = 1 / fs
    z = 1 / (2 * q)
    pad = np.zeros(int((1 / (freqs.min() * np.sqrt(1 - z * z))) // dt) + 1)
    rows = []
    for f in freqs:
        out = {}
        for name, mk in [("acc", coeffs_acc), ("pv", coeffs_pv)]:
            b, a = mk(f, q, dt)
            y, zf = sig.lfilter(b, a, x, zi=np.zeros(2))
            r, _ = sig.lfilter(b, a, pad, zi=zf)
            out[name] = (y, r)
        y, r = out["acc"]
        pos, neg = max(y.max(), r.max()), -min(y.min(), r.min())
        pv = max(np.abs(out["pv"][0]).max(), np.abs(out["pv"][1]).max())
        rows.append(dict(frequency_hz=float(f), maximax=float(max(abs(pos), abs(neg))), positive=float(pos),
                         negative=float(neg), primary=float(np.abs(y).max()), residual=float(np.abs(r).max()),
                         pseudo_velocity=float(pv)))
    return rows, len(pad)


def grid(fmin, fmax, n):
    k = np.arange(0, int(np.floor(n * np.log2(fmax / fmin) + 1e-9)) + 1)
    return fmin * 2.0 ** (k / n)


out = {"command": "python3 data/signal-refs/make_srs_refs.py", "numpy": np.__version__,
       "scipy": scipy.__version__, "endaq": endaq.__version__, "cases": []}

# Synthetic record: 2 ms half-sine of 50 g, a 900 Hz decaying sinusoid, noise, a 0.3 g offset.
fs, q = 20000.0, 10.0
t = np.arange(int(0.12 * fs)) / fs
x = np.where((t >= 0.01) & (t < 0.012), 50 * np.sin(np.pi * (t - 0.01) / 0.002), 0.0)
x += 20 * np.exp(-(t - 0.01) / 0.01) * np.sin(2 * np.pi * 900 * (t - 0.01)) * (t >= 0.01)
x += np.random.default_rng(7).normal(0, 0.2, t.size) + 0.3
freqs = grid(20.0, 5000.0, 12)
xm = x - x.mean()
rows, npad = spectrum(xm, fs, freqs, q)
out["cases"].append(dict(name="synthetic", fs_hz=fs, q=q, offset="mean", residual_samples=npad,
                         coefficient_check=check_coefficients(freqs[-1], q, 1 / fs),
                         samples=[float(v) for v in x], srs=rows))

# Third-party record, no offset removal (endaq does none).
d = np.loadtxt(root + "/data/realdata/hrshm-pcb-shock/acc_base_a0_first5ms.csv", delimiter=",", skiprows=1)
dt = (d[-1, 0] - d[0, 0]) / (len(d) - 1)
fs = 1 / dt
freqs = grid(100.0, 20000.0, 12)
rows, npad = spectrum(d[:, 1], fs, freqs, q)
df = pd.DataFrame({"a": d[:, 1]}, index=pd.Index(d[:, 0], name="timestamp"))
res = shock.shock_spectrum(df, freqs=freqs, damp=1 / (2 * q), mode="srs", two_sided=True, max_time=None)
for r, neg, pos in zip(rows, res.neg["a"].to_numpy(), res.pos["a"].to_numpy()):
    r["endaq_negative"], r["endaq_positive"] = float(neg), float(pos)
out["cases"].append(dict(name="hrshm", fs_hz=fs, q=q, offset="none", residual_samples=npad,
                         coefficient_check=check_coefficients(freqs[-1], q, dt),
                         file="data/realdata/hrshm-pcb-shock/acc_base_a0_first5ms.csv", srs=rows))
for c in out["cases"]:
    print(c["name"], "fs", c["fs_hz"], "pad", c["residual_samples"], "coefficient check", c["coefficient_check"],
          "points", len(c["srs"]))
hr = out["cases"][1]["srs"]
print("endaq vs lfilter, max rel:", max(max(abs(r["endaq_positive"] - r["positive"]) / r["maximax"],
                                            abs(r["endaq_negative"] - r["negative"]) / r["maximax"]) for r in hr))
json.dump(out, open(root + "/data/signal-refs/srs_refs.json", "w"), indent=0)
