"""Reference Welch PSD / CSD / coherence values computed by scipy.signal, for tests/signal_welch.rs.

Regenerate (from the repository root):
    python3 data/signal-refs/make_refs.py
This writes data/signal-refs/welch_refs.json. Made with scipy 1.17 / numpy (see the `versions` key).
Inputs x, y are stored in the JSON (repr round-trip floats) so Rust reads the same samples.
"""
import json, sys
import numpy as np
import scipy
import scipy.signal as ss

rng = np.random.default_rng(20261121)
n = 6000
fs = 1000.0
t = np.arange(n) / fs
# Noise + tones + a linear trend and offset, so that the detrend choice matters.
x = rng.standard_normal(n) + 2.0 * np.sin(2 * np.pi * 60.0 * t) + 0.5 * t + 3.0
y = np.convolve(x, [0.5, 0.3, -0.2], mode="same") + 0.3 * rng.standard_normal(n)

cases = [
    dict(window="hann", detrend="constant", nperseg=256, overlap=0.5),
    dict(window="hamming", detrend="linear", nperseg=255, overlap=0.25),
    dict(window="flattop", detrend=False, nperseg=512, overlap=0.75),
    dict(window="boxcar", detrend="constant", nperseg=101, overlap=0.0),
    dict(window="hann", detrend="linear", nperseg=1000, overlap=0.6),
    dict(window="hamming", detrend=False, nperseg=333, overlap=0.9),
]
out = {"versions": {"scipy": scipy.__version__, "numpy": np.__version__},
       "command": "python3 data/signal-refs/make_refs.py",
       "fs": fs, "x": x.tolist(), "y": y.tolist(), "welch": [], "csd": []}
for c in cases:
    noverlap = int(np.floor(c["overlap"] * c["nperseg"]))
    kw = dict(fs=fs, window=c["window"], nperseg=c["nperseg"], noverlap=noverlap, detrend=c["detrend"])
    f, p = ss.welch(x, **kw)
    _, pyy = ss.welch(y, **kw)
    _, pxy = ss.csd(x, y, **kw)
    _, coh = ss.coherence(x, y, **kw)
    d = "none" if c["detrend"] is False else c["detrend"]
    rec = dict(window=c["window"], detrend=d, nperseg=c["nperseg"], overlap=c["overlap"], noverlap=noverlap,
               f=f.tolist(), pxx=p.tolist())
    out["welch"].append(rec)
    out["csd"].append(dict(window=c["window"], detrend=d, nperseg=c["nperseg"], overlap=c["overlap"],
                           pyy=pyy.tolist(), pxy_re=pxy.real.tolist(), pxy_im=pxy.imag.tolist(), coh=coh.tolist()))
json.dump(out, open(__file__.replace("make_refs.py", "welch_refs.json"), "w"))
print("wrote", len(cases), "cases")
