#!/usr/bin/env python3
"""Compare two trees of geoslip results, as written by `geoslip run --out` (for example the examples
run before and after a change that must not change behaviour).

    python3 scripts/compare-results.py BEFORE AFTER [--tolerance 1e-9]

For every `summary.json` under BEFORE it compares, against the same file under AFTER:
- the status, the events and the factors of safety;
- per step: the load and strength factors, the iteration and cutback counts, the force residual,
  the state changes, the re-associations and the reinforcement force balance;
- the solver's counts (analyses, factorisations, solves, equilibrium iterations);
and every CSV file beside it (history.csv, and each step's tables when the runs wrote them with
`geoslip run --csv`) value by value, and every dataset of `results.h5` (a build with the `hdf5`
feature; read with h5py, Debian's python3-h5py) value by value. A single-precision field (the
default, `--field-precision single`) may differ by one unit in its last place: two values within the
tolerance can round to neighbouring 4-byte floats.

A number is "identical" when its text is the same; otherwise the relative difference
|a − b| / max(|a|, |b|, 1e-300) must stay below the tolerance. Timings are not compared. Prints one
line per run folder and exits with 1 when anything differs beyond the tolerance or is missing.
"""

import argparse
import csv
import json
import math
import os
import sys

TIMING_KEYS = {"seconds", "total_seconds"}
STEP_KEYS = [
    "stage", "step", "load_factor", "strength_factor", "iterations", "cutbacks", "force_residual",
    "redundant_rows", "state_changes", "reassociations", "sliding_points", "yielding_points",
    "contact_points", "balance",
]
STATS_KEYS = ["analyses", "factorizations", "solves", "iterations", "max_relative_residual", "warnings"]


class Tally:
    def __init__(self, tolerance):
        self.tolerance = tolerance
        self.identical = 0
        self.close = 0
        self.worst = 0.0
        self.failures = []

    def number(self, where, a, b):
        if a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b)):
            self.identical += 1
            return
        rel = abs(a - b) / max(abs(a), abs(b), 1e-300)
        self.worst = max(self.worst, rel)
        if rel <= self.tolerance:
            self.close += 1
        else:
            self.failures.append(f"{where}: {a!r} against {b!r} (relative {rel:.2e})")

    def value(self, where, a, b):
        """Compare two JSON values, recursively; text must match exactly."""
        if isinstance(a, bool) or isinstance(b, bool) or a is None or b is None:
            if a != b:
                self.failures.append(f"{where}: {a!r} against {b!r}")
            else:
                self.identical += 1
        elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
            self.number(where, float(a), float(b))
        elif isinstance(a, str) and isinstance(b, str):
            if a == b:
                self.identical += 1
            else:
                self.text(where, a, b)
        elif isinstance(a, list) and isinstance(b, list):
            if len(a) != len(b):
                self.failures.append(f"{where}: {len(a)} entries against {len(b)}")
                return
            for i, (x, y) in enumerate(zip(a, b)):
                self.value(f"{where}[{i}]", x, y)
        elif isinstance(a, dict) and isinstance(b, dict):
            for k in sorted(set(a) | set(b)):
                if k in TIMING_KEYS or k.endswith("_seconds"):
                    continue
                if k not in a or k not in b:
                    self.failures.append(f"{where}.{k}: only in {'before' if k in a else 'after'}")
                    continue
                self.value(f"{where}.{k}", a[k], b[k])
        else:
            self.failures.append(f"{where}: {a!r} against {b!r}")

    def text(self, where, a, b):
        """Strings that differ only in the numbers they quote (a state change 'T = 1.23')."""
        ta, tb = split_numbers(a), split_numbers(b)
        if len(ta) != len(tb) or any(type(x) is not type(y) or (isinstance(x, str) and x != y) for x, y in zip(ta, tb)):
            self.failures.append(f"{where}: {a!r} against {b!r}")
            return
        for x, y in zip(ta, tb):
            if isinstance(x, float):
                self.number(where, x, y)


def split_numbers(s):
    import re
    out = []
    for part in re.split(r"(-?\d+\.\d+(?:e[-+]?\d+)?)", s):
        if re.fullmatch(r"-?\d+\.\d+(?:e[-+]?\d+)?", part):
            out.append(float(part))
        elif part:
            out.append(part)
    return out


def compare_csv(tally, where, a_path, b_path):
    with open(a_path, newline="") as fa, open(b_path, newline="") as fb:
        ra, rb = list(csv.reader(fa)), list(csv.reader(fb))
    if len(ra) != len(rb):
        tally.failures.append(f"{where}: {len(ra)} rows against {len(rb)}")
        return
    for i, (x, y) in enumerate(zip(ra, rb)):
        if len(x) != len(y):
            tally.failures.append(f"{where} row {i}: {len(x)} columns against {len(y)}")
            continue
        for j, (p, q) in enumerate(zip(x, y)):
            if p == q:
                tally.identical += 1
                continue
            try:
                tally.number(f"{where} row {i} column {j}", float(p), float(q))
            except ValueError:
                tally.failures.append(f"{where} row {i} column {j}: {p!r} against {q!r}")


def compare_h5(tally, where, a_path, b_path):
    """Every dataset of one results.h5 against the same dataset of the other."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        tally.failures.append(f"{where}: cannot compare without h5py (install python3-h5py)")
        return
    with h5py.File(a_path, "r") as fa, h5py.File(b_path, "r") as fb:
        names = []
        fa.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
        for name in sorted(names):
            if name not in fb:
                tally.failures.append(f"{where}:{name}: missing after")
                continue
            x, y = fa[name][()], fb[name][()]
            if x.shape != y.shape:
                tally.failures.append(f"{where}:{name}: shape {x.shape} against {y.shape}")
                continue
            x, y = np.ravel(x), np.ravel(y)
            same = (x == y) | (np.isnan(x) & np.isnan(y)) if x.dtype.kind == "f" else x == y
            if x.dtype == np.float32 and y.dtype == np.float32:
                # a single-precision field: two values within the tolerance may round to
                # neighbouring floats, so one unit in the last place counts as the same
                scale = np.maximum(np.abs(x), np.abs(y)).astype(np.float64)
                same |= np.abs(x.astype(np.float64) - y.astype(np.float64)) <= 2.0**-23 * scale
            tally.identical += int(np.count_nonzero(same))
            for i in np.flatnonzero(~same):
                tally.number(f"{where}:{name}[{i}]", float(x[i]), float(y[i]))


def compare_run(before, after, folder, tolerance):
    tally = Tally(tolerance)
    with open(os.path.join(before, folder, "summary.json")) as f:
        a = json.load(f)
    b_path = os.path.join(after, folder, "summary.json")
    if not os.path.exists(b_path):
        tally.failures.append(f"{folder}: no summary.json after")
        return tally
    with open(b_path) as f:
        b = json.load(f)
    for key in ["status", "error", "events", "factors_of_safety", "unknowns"]:
        tally.value(key, a.get(key), b.get(key))
    if len(a["steps"]) != len(b["steps"]):
        tally.failures.append(f"steps: {len(a['steps'])} against {len(b['steps'])}")
    for i, (sa, sb) in enumerate(zip(a["steps"], b["steps"])):
        for key in STEP_KEYS:
            tally.value(f"steps[{i}].{key}", sa.get(key), sb.get(key))
    for key in STATS_KEYS:
        tally.value(f"solver_stats.{key}", a["solver_stats"].get(key), b["solver_stats"].get(key))
    for root, _, files in os.walk(os.path.join(before, folder)):
        for name in sorted(files):
            if name.endswith(".csv") or name == "results.h5":
                rel = os.path.relpath(os.path.join(root, name), before)
                other = os.path.join(after, rel)
                if not os.path.exists(other):
                    tally.failures.append(f"{rel}: missing after")
                elif name.endswith(".csv"):
                    compare_csv(tally, rel, os.path.join(root, name), other)
                else:
                    compare_h5(tally, rel, os.path.join(root, name), other)
    return tally


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--tolerance", type=float, default=1e-9)
    args = parser.parse_args()
    folders = sorted(
        os.path.relpath(root, args.before)
        for root, _, files in os.walk(args.before)
        if "summary.json" in files
    )
    if not folders:
        print(f"no summary.json under {args.before}")
        return 1
    bad = 0
    print(f"{'run':<48} {'identical':>10} {'within tol':>10} {'worst rel':>10}  verdict")
    for folder in folders:
        t = compare_run(args.before, args.after, folder, args.tolerance)
        verdict = "bit for bit" if not t.failures and t.close == 0 else ("same within tolerance" if not t.failures else "DIFFERS")
        print(f"{folder:<48} {t.identical:>10} {t.close:>10} {t.worst:>10.1e}  {verdict}")
        for f in t.failures[:10]:
            print(f"    {f}")
        if len(t.failures) > 10:
            print(f"    and {len(t.failures) - 10} more")
        bad += bool(t.failures)
    print(f"{len(folders)} runs compared, {bad} differ beyond {args.tolerance:g}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
