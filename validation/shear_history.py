#!/usr/bin/env python3
"""Neo-Hookean capsule in simple shear at Ca = 0.3 and 0.6 (lambda = 1): the history D(t) from
rest, capflow at three resolutions against the published histories (docs/validation.md section
15.3).

Usage: validation/shear_history.py [--exe build/src/app/capflow] [--reuse]

Runs capflow (adaptive steps, time.tolerance 1e-6, to the last listed time) at NE=6 NB=10,
NE=10 NB=12 and NE=6 NB=14 into runs/validation/shear_history_*, reads D from each
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
MESHES = [(6, 10), (10, 12), (6, 14)]
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


def run(exe, ca, ne, nb, reuse):
    t_end = max(PUBLISHED[ca])
    out = os.path.join(ROOT, "runs", "validation", f"shear_history_ca{ca:g}_ne{ne}_nb{nb}")
    ts = os.path.join(out, "timeseries.csv")
    if not (reuse and os.path.exists(ts)):
        control = {
            "description": f"NH simple shear Ca={ca:g} from rest, NE={ne} NB={nb} (shear_history.py)",
            "capsule": {"law": "neo-hookean"},
            "mesh": {"elements": ne, "nb": nb},
            "flow": {"type": "simple-shear"},
            "time": {"dt": "auto", "t_end": t_end, "tolerance": 1e-6},
            "ca": ca,
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
    print("| Ca | t | " + " | ".join(f"capflow NE={ne} NB={nb}" for ne, nb in MESHES) + " | " +
          " | ".join(CODES) + " |")
    print("|---" * (2 + len(MESHES) + len(CODES)) + "|")
    for ca, rows in PUBLISHED.items():
        series = {m: run(a.exe, ca, *m, a.reuse) for m in MESHES}
        for t, theirs in rows.items():
            ours = [f"{at(series[m], t):.4f}" for m in MESHES]
            cells = ["" if v is None else f"{v:.3f}" for v in theirs]
            print(f"| {ca:g} | {t:g} | " + " | ".join(ours) + " | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
