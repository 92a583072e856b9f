#!/usr/bin/env python3
"""Compares two JSON files number by number and reports the largest relative difference.

Usage: compare_json.py A.json B.json [--floor F]

Both files must have the same structure (keys, list lengths, non-numeric values); numbers
are compared as |a - b| / max(|a|, |b|, F), with F (default 1e-300) a floor that keeps
exact zeros from dividing by zero. Prints the maximum relative difference and the path where
it occurs; exits 1 when the structures differ.
"""

import json
import sys


def walk(a, b, path, worst, mismatches, floor):
    if isinstance(a, bool) or isinstance(b, bool) or a is None or b is None:
        if a != b:
            mismatches.append(f"{path}: {a!r} != {b!r}")
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
        scale = max(abs(a), abs(b), floor)
        rel = abs(a - b) / scale
        if rel > worst[0]:
            worst[0], worst[1] = rel, f"{path}: {a!r} vs {b!r}"
    elif isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            mismatches.append(f"{path}: keys differ {sorted(a.keys() ^ b.keys())}")
        for k in a.keys() & b.keys():
            walk(a[k], b[k], f"{path}.{k}", worst, mismatches, floor)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            mismatches.append(f"{path}: lengths {len(a)} != {len(b)}")
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", worst, mismatches, floor)
    elif a != b:
        mismatches.append(f"{path}: {a!r} != {b!r}")


def main():
    args = sys.argv[1:]
    floor = 1e-300
    if "--floor" in args:
        i = args.index("--floor")
        floor = float(args[i + 1])
        del args[i : i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    with open(args[0]) as fa, open(args[1]) as fb:
        a, b = json.load(fa), json.load(fb)
    worst = [0.0, "(no numbers differ)"]
    mismatches = []
    walk(a, b, "$", worst, mismatches, floor)
    print(f"max relative difference {worst[0]:.3e} at {worst[1]}")
    for m in mismatches:
        print(f"structure: {m}")
    sys.exit(1 if mismatches else 0)


if __name__ == "__main__":
    main()
