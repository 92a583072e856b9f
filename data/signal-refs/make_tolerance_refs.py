"""Tolerance-band figures of the VibControl pilot PSD against data/signal-refs/vibcontrol_profile.toml
(and the same profile scaled), computed independently with numpy, for tests/signal_bands.rs.

Regenerate (from the repository root):
    python3 data/signal-refs/make_tolerance_refs.py
Definitions: lines with profile_f[0] <= f <= profile_f[-1]; reference = log-log interpolation;
excursion = 10 log10(measured / reference); measured Grms = sqrt(trapezoid over those lines);
reference Grms = sqrt(exact integral of the log-log segments).
"""
import json, tomllib
import numpy as np

root = __file__.rsplit("/data/", 1)[0]
prof = np.array(tomllib.load(open(root + "/data/signal-refs/vibcontrol_profile.toml", "rb"))["profile_g2_hz"])
d = np.loadtxt(root + "/data/realdata/pyuff-vibcontrol-psd/vibcontrol_random_pilot_psd.csv", delimiter=",", skiprows=1)
f, p = d[:, 0], d[:, 1]
out = {"command": "python3 data/signal-refs/make_tolerance_refs.py", "numpy": np.__version__, "cases": []}
for scale in [1.0, 1.25, 2.0]:
    pr = prof.copy()
    pr[:, 1] *= scale
    m = (f >= pr[0, 0]) & (f <= pr[-1, 0])
    r = np.exp(np.interp(np.log(f[m]), np.log(pr[:, 0]), np.log(pr[:, 1])))
    db = 10 * np.log10(p[m] / r)
    s = 0.0
    for (x0, y0), (x1, y1) in zip(pr[:-1], pr[1:]):
        k = np.log(y1 / y0) / np.log(x1 / x0)
        s += y0 * x0 / (k + 1) * ((x1 / x0) ** (k + 1) - 1)
    meas = np.sqrt(np.trapezoid(p[m], f[m]))
    i = int(np.argmax(np.abs(db)))
    out["cases"].append(dict(scale=scale, lines=int(m.sum()), alarm=float(np.mean(np.abs(db) > 3)),
                             abort=float(np.mean(np.abs(db) > 6)), worst_db=float(db[i]), worst_hz=float(f[m][i]),
                             measured_grms=float(meas), reference_grms=float(np.sqrt(s))))
json.dump(out, open(root + "/data/signal-refs/tolerance_refs.json", "w"), indent=1)
print(out["cases"])
