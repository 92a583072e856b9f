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


def main(frf_csv, satqual_json):
    data = np.loadtxt(frf_csv, delimiter=",", skiprows=1)
    # sdypy keeps the lines below the one nearest `upper`, that line excluded; satqual keeps
    # the line nearest UPPER. Handing sdypy one line more, with `upper` on it, fits both on
    # the same lines (and the same Ts = 1/(2 f_top)).
    top = int(np.argmin(np.abs(data[:, 0] - UPPER)))
    freq = data[: top + 2, 0]
    frf = data[: top + 2, 1] + 1j * data[: top + 2, 2]
    ours = json.load(open(satqual_json))["modes"]
    model = EMA.Model(
        frf=frf[None, :],
        freq=freq,
        lower=LOWER,
        upper=freq[-1],
        pol_order_high=POL_ORDER_HIGH,
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
        "frf": "H1 force->acceleration of data/realdata/pyfrf-impact impact_1..5, boxcar, nperseg 25600",
        "lower_hz": LOWER,
        "upper_hz": UPPER,
        "pol_order_high": POL_ORDER_HIGH,
        "same_order": same_order,
        "sdypy_selection": [
            {"seed_hz": s, "frequency_hz": float(f), "damping_ratio": float(x)}
            for s, f, x in zip(seeds, model.nat_freq, model.nat_xi)
        ],
    }
    json.dump(out, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
