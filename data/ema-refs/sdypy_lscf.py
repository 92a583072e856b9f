"""Peer reference for `satqual ema`: sdypy-EMA's LSCF on the FRFs that satqual exports.

Made with sdypy-EMA 0.31.0 (pip install sdypy-EMA) and numpy; run from the repository root:

    satqual ema data/realdata/pyfrf-impact/impact_*.csv --input force --output acceleration \\
        --nperseg 25600 --window boxcar --fmin 50 --fmax 6400 --order-max 100 \\
        --export-frf /tmp/pyfrf-impact-frf.csv --json > /tmp/pyfrf-impact-ema.json
    python3 data/ema-refs/sdypy_lscf.py /tmp/pyfrf-impact-frf.csv /tmp/pyfrf-impact-ema.json \\
        > data/ema-refs/pyfrf-impact-sdypy.json

The FRF is H1 = force -> acceleration averaged over the 5 hits (one 25600-sample boxcar
segment each, 1 Hz lines). sdypy fits the same lines (50-6400 Hz) with the same highest order
(pol_order_high = 50: polynomial orders 2, 4, ..., 100, those of --order-max 100).

Measured FRFs stored in a UFF file are read here by pyuff 2.5.8 (an independent reader of the
same file), not from satqual's export:

    satqual ema data/realdata/dialects/pyuff/measurement.uff --fmin 1 --fmax 999 \
        --json > /tmp/measurement-ema.json
    python3 data/ema-refs/sdypy_lscf.py --uff data/realdata/dialects/pyuff/measurement.uff \
        /tmp/measurement-ema.json 1 999 30 > data/ema-refs/pyuff-measurement-sdypy.json

(band 1-999 Hz: the file's last line, 1000 Hz, is the one sdypy needs beyond the band; the
default --order-max 60 is pol_order_high 30). The dam's 26 FRFs, the same way:

    satqual ema data/realdata/dialects/uff-dam/dam0.unv --fmin 0.5 --fmax 12.46875 \
        --json > /tmp/dam-ema.json
    python3 data/ema-refs/sdypy_lscf.py --uff data/realdata/dialects/uff-dam/dam0.unv \
        /tmp/dam-ema.json 0.5 12.46875 30 > data/ema-refs/uff-dam-sdypy.json

Two references are written:
- `same_order`: for each mode satqual selected, sdypy's pole of the same model order nearest in
  frequency. It compares the estimators, pole for pole.
- `sdypy_selection`: sdypy's own choice, `select_closest_poles` seeded with satqual's
  frequencies, with its default stability tolerances (0.1 % frequency, 5 % damping): for each
  seed, sdypy's stable pole nearest to it, of whatever order.
"""

import json
import sys

import numpy as np
from sdypy import EMA

LOWER, UPPER, POL_ORDER_HIGH = 50.0, 6400.0, 50


def freq_damp(pole):
    w = abs(pole)
    return w / (2 * np.pi), -pole.real / w


def csv_frfs(frf_csv):
    data = np.loadtxt(frf_csv, delimiter=",", skiprows=1)
    return data[:, 0], (data[:, 1] + 1j * data[:, 2])[None, :]


def uff_frfs(uff_path):
    import pyuff

    sets = [d for d in pyuff.UFF(uff_path).read_sets() if d.get("func_type") == 4]
    return np.asarray(sets[0]["x"]), np.array([d["data"] for d in sets])


def main(freq_all, frf_all, satqual_json, lower, upper, pol_order_high, source):
    # sdypy keeps the lines below the one nearest `upper`, that line excluded; satqual keeps
    # the line nearest `upper`. Handing sdypy one line more, with `upper` on it, fits both on
    # the same lines (and the same Ts = 1/(2 f_top)).
    top = int(np.argmin(np.abs(freq_all - upper)))
    freq = freq_all[: top + 2]
    frf = frf_all[:, : top + 2]
    ours = json.load(open(satqual_json))["modes"]
    model = EMA.Model(
        frf=frf,
        freq=freq,
        lower=lower,
        upper=freq[-1],
        pol_order_high=pol_order_high,
        frf_form="accelerance",
    )
    model.get_poles(method="lscf", show_progress=False)
    same_order = []
    for m in ours:
        poles = [p for p in model.all_poles[m["order"] // 2 - 1] if p.imag > 0 and p.real < 0]
        f, z = min((freq_damp(p) for p in poles), key=lambda fz: abs(fz[0] - m["frequency_hz"]))
        same_order.append({"order": m["order"], "frequency_hz": f, "damping_ratio": z})
    seeds = [m["frequency_hz"] for m in ours]
    model.select_closest_poles(seeds)
    out = {
        "tool": "sdypy-EMA 0.31.0: Model.get_poles(method='lscf'); select_closest_poles",
        "frf": source,
        "lower_hz": lower,
        "upper_hz": upper,
        "pol_order_high": pol_order_high,
        "same_order": same_order,
        "sdypy_selection": [
            {"seed_hz": s, "frequency_hz": float(f), "damping_ratio": float(x)}
            for s, f, x in zip(seeds, model.nat_freq, model.nat_xi)
        ],
    }
    json.dump(out, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    if sys.argv[1] == "--uff":
        uff, ours_json, lo, hi, order = sys.argv[2:7]
        f, h = uff_frfs(uff)
        main(f, h, ours_json, float(lo), float(hi), int(order),
             f"the FRFs (function type 4) of {uff}, read by pyuff 2.5.8")
    else:
        f, h = csv_frfs(sys.argv[1])
        main(f, h, sys.argv[2], LOWER, UPPER, POL_ORDER_HIGH,
             "H1 force->acceleration of data/realdata/pyfrf-impact impact_1..5, boxcar, nperseg 25600")
