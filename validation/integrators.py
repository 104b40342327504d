#!/usr/bin/env python3
"""time.method "chebyshev" against "cash-karp": the red blood cell in shear (Evans-Fung, axis
along the flow, Skalak C = 10, Eb = 5e-3 about its own shape, Ca = 0.1, NE 6 NB 10) from rest to
t = 1. The reference is Cash-Karp at tolerance 1e-9 (its steps are stability-limited, so its
error is far below that of the other runs). For each run: the largest difference from the
reference over the timeseries rows (every 0.05) in D, the inclination, the volume and the
extreme principal tensions, and the velocity evaluations. Prints a markdown table.

  validation/integrators.py [--capflow build/src/app/capflow] [--t-end 1]
"""
import argparse
import csv
import json
import os
import re
import subprocess
import tempfile

RUNS = [("cash-karp", 1e-9), ("cash-karp", 1e-6), ("chebyshev", 1e-6), ("chebyshev", 1e-7),
        ("chebyshev", 1e-8)]
COLUMNS = [("D", "D"), ("inclination_deg", "inclination (deg)"), ("volume", "volume"),
           ("tau_max", "tau max"), ("tau_min", "tau min")]


def run(capflow, tmp, method, tol, t_end):
    out = os.path.join(tmp, "%s_%g" % (method, tol))
    c = {"capsule": {"law": "skalak", "C": 10, "shape": {"biconcave": {"axis": "x"}},
                     "bending": {"modulus": 0.005, "model": "reference"}},
         "mesh": {"elements": 6, "nb": 10}, "flow": {"type": "simple-shear"}, "ca": 0.1,
         "time": {"t_end": t_end, "method": method, "tolerance": tol},
         "output": {"dir": out, "csv_every": 0.05, "png": False, "mp4": False}}
    with open(out + ".json", "w") as f:
        json.dump(c, f)
    r = subprocess.run([capflow, "run", out + ".json"], capture_output=True, text=True)
    end = [l for l in r.stdout.splitlines() + r.stderr.splitlines() if l.startswith("end")]
    if not end or "t_end reached" not in end[-1]:
        raise RuntimeError("%s %g failed: %s" % (method, tol, (r.stderr or r.stdout)[-300:]))
    evals = int(re.search(r"velocity evaluations=(\d+)", end[-1]).group(1))
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return evals, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--capflow", default="build/src/app/capflow")
    ap.add_argument("--t-end", type=float, default=1.0)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        res = [(m, tol) + run(a.capflow, tmp, m, tol, a.t_end) for m, tol in RUNS]
    ref = res[0][3]
    print("| method | tolerance | velocity evaluations | " +
          " | ".join("max diff. %s" % label for _, label in COLUMNS) + " |")
    print("|---|---:|---:|" + "---:|" * len(COLUMNS))
    for m, tol, evals, rows in res:
        if rows is ref:
            diffs = ["reference"] * len(COLUMNS)
        else:
            assert len(rows) == len(ref)
            diffs = ["%.1e" % max(abs(float(x[c]) - float(y[c])) for x, y in zip(rows, ref))
                     for c, _ in COLUMNS]
        print("| %s | %g | %d | %s |" % (m, tol, evals, " | ".join(diffs)))


if __name__ == "__main__":
    main()
