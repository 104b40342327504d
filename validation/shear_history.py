#!/usr/bin/env python3
"""Neo-Hookean capsule in simple shear at Ca = 0.3 and 0.6 (lambda = 1): the history D(t) from
rest, capflow at three resolutions against the published histories (docs/validation.md section
15.3).

Usage: validation/shear_history.py [--exe build/src/app/capflow] [--reuse]

Runs capflow (adaptive steps, time.tolerance 1e-6, to the last listed time) at NE=6 NB=10,
NE=10 NB=12 and NE=6 NB=14, and at NE=6 NB=10 with numerics.quadrature_scale 2 and
time.tolerance 1e-8, into runs/validation/shear_history_*, reads D from each
timeseries.csv and prints a markdown table of D at the listed times with the published values.
The published values are read off the authors' figures (Ca based on Gs = E_s / 3; +-0.005):
Pozrikidis 1995 (boundary elements, to t = 2), Ramanujan & Pozrikidis 1998 (boundary
elements), Eggleton & Popel 1998 (immersed boundary, Ca = 0.6 to t = 1.3), Doddi & Bagchi 2008
(front tracking) and Huet's Basilisk front-tracking capsules (walls at +-4a).
"""
import argparse
import bisect
import csv
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# (label, NE, NB, quadrature scale, time tolerance): three resolutions, and NE=6 NB=10 with every
# quadrature order doubled and a 100x tighter step tolerance (the numerics' share of D)
RUNS = [("NE=6 NB=10", 6, 10, 1.0, 1e-6), ("NE=10 NB=12", 10, 12, 1.0, 1e-6),
        ("NE=6 NB=14", 6, 14, 1.0, 1e-6), ("NE=6 NB=10, quadrature x2, tolerance 1e-8", 6, 10, 2.0, 1e-8)]
CODES = ["Pozrikidis 1995", "Ramanujan & Pozrikidis 1998", "Eggleton & Popel 1998",
         "Doddi & Bagchi 2008", "Huet (Basilisk)"]
# Ca: {t: D of each code in CODES at t, read off the published curves (None: not published
# there, or too sparsely digitised to interpolate)}.
PUBLISHED = {
    0.3: {0.5: [0.201, 0.197, None, None, 0.204],
          1.0: [0.311, 0.306, None, None, 0.312],
          2.0: [None, 0.377, None, None, None],
          5.5: [None, 0.385, None, 0.392, 0.382]},
    0.6: {0.5: [0.220, 0.217, 0.225, 0.225, 0.223],
          1.0: [0.366, 0.361, 0.368, 0.374, 0.368],
          2.0: [0.488, 0.480, None, 0.481, 0.480],
          3.5: [None, 0.508, None, 0.497, None],
          8.0: [None, 0.500, None, 0.496, 0.496]},
}


def run(exe, ca, spec, reuse):
    _, ne, nb, scale, tol = spec
    t_end = max(PUBLISHED[ca])
    suffix = "" if (scale, tol) == (1.0, 1e-6) else f"_q{scale:g}_tol{tol:g}"
    out = os.path.join(ROOT, "runs", "validation", f"shear_history_ca{ca:g}_ne{ne}_nb{nb}{suffix}")
    ts = os.path.join(out, "timeseries.csv")
    if not (reuse and os.path.exists(ts)):
        control = {
            "description": f"NH simple shear Ca={ca:g} from rest, NE={ne} NB={nb} (shear_history.py)",
            "capsule": {"law": "neo-hookean"},
            "mesh": {"elements": ne, "nb": nb},
            "flow": {"type": "simple-shear"},
            "time": {"dt": "auto", "t_end": t_end, "tolerance": tol},
            "ca": ca,
            "numerics": {"quadrature_scale": scale},
            "output": {"dir": out, "csv_every": 0.05},
        }
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump(control, f)
        try:
            subprocess.run([exe, "run", "--overwrite", f.name], check=True,
                           stdout=subprocess.DEVNULL)
        finally:
            os.unlink(f.name)
    with open(ts) as f:
        rows = list(csv.DictReader(f))
    return [float(r["t"]) for r in rows], [float(r["D"]) for r in rows]


def at(series, t):
    ts, ds = series
    i = bisect.bisect_left(ts, t - 1e-12)
    if i >= len(ts):
        sys.exit(f"shear_history: the run ends before t = {t}")
    if abs(ts[i] - t) < 1e-9 or i == 0:
        return ds[i]
    a = (t - ts[i - 1]) / (ts[i] - ts[i - 1])
    return ds[i - 1] + a * (ds[i] - ds[i - 1])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "src", "app", "capflow"))
    p.add_argument("--reuse", action="store_true")
    a = p.parse_args()
    print("| Ca | t | " + " | ".join(f"capflow {r[0]}" for r in RUNS) + " | " +
          " | ".join(CODES) + " |")
    print("|---" * (2 + len(RUNS) + len(CODES)) + "|")
    for ca, rows in PUBLISHED.items():
        series = [run(a.exe, ca, r, a.reuse) for r in RUNS]
        for t, theirs in rows.items():
            ours = [f"{at(sr, t):.4f}" for sr in series]
            cells = ["" if v is None else f"{v:.3f}" for v in theirs]
            print(f"| {ca:g} | {t:g} | " + " | ".join(ours) + " | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
