#!/usr/bin/env python3
"""The adaptive step with bending (Milestone 15): how the stable dt and the cost of a shear time
fall with the bending modulus Eb and with NB.

A red blood cell (Evans-Fung, axis along the flow, Skalak C = 10, bending about its own shape)
in simple shear at Ca = 0.1, NE = 6, from rest to t = 0.5 by capflow run's adaptive steps
(ARKODE, the default tolerance), one run per setting on 2 threads. Prints a markdown table: the
median accepted dt over the last half of the run (from timeseries.csv's dt column), steps,
rejected steps, velocity evaluations, and the wall time per unit of G t.

  benchmarks/capsule/bending_steps.py [--capflow build/src/app/capflow] [--t-end 0.5]
      [--settings 0:10,0.005:10,0.02:10,0.005:8,0.005:12]   (Eb:NB pairs)
"""
import argparse
import csv
import json
import os
import re
import statistics
import subprocess
import tempfile


def control(eb, nb, t_end, out):
    capsule = {"law": "skalak", "C": 10, "shape": {"biconcave": {"axis": "x"}}}
    if eb > 0:
        capsule["bending"] = {"modulus": eb, "model": "reference"}
    return {"capsule": capsule, "mesh": {"elements": 6, "nb": nb},
            "flow": {"type": "simple-shear"}, "ca": 0.1, "time": {"t_end": t_end},
            "output": {"dir": out, "csv_every": 0.02, "png": False, "mp4": False}}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--capflow", default="build/src/app/capflow")
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("--settings", default="0:10,0.005:10,0.02:10,0.005:8,0.005:12")
    a = ap.parse_args()
    print("| Eb | NB | median dt (t > %g) | steps (rejected) | velocity evaluations | wall per G t |"
          % (a.t_end / 2))
    print("|---:|---:|---:|---|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for s in a.settings.split(","):
            eb, nb = float(s.split(":")[0]), int(s.split(":")[1])
            out = os.path.join(tmp, "eb%g_nb%d" % (eb, nb))
            path = out + ".json"
            with open(path, "w") as f:
                json.dump(control(eb, nb, a.t_end, out), f)
            r = subprocess.run([a.capflow, "run", path], capture_output=True, text=True)
            end = [l for l in r.stdout.splitlines() + r.stderr.splitlines() if l.startswith("end")]
            if not end:
                print("| %g | %d | failed: %s | | | |" % (eb, nb, (r.stderr or r.stdout)[-200:]))
                continue
            m = re.search(r"steps=(\d+) \(rejected (\d+)\) velocity evaluations=(\d+) wall=([0-9.]+) s",
                          end[-1])
            with open(os.path.join(out, "timeseries.csv")) as f:
                rows = [x for x in csv.DictReader(f) if float(x["t"]) > a.t_end / 2]
            dts = [float(x["dt"]) for x in rows if float(x["dt"]) > 0]
            print("| %g | %d | %.2e | %s (%s) | %s | %.1f s |" % (
                eb, nb, statistics.median(dts), m.group(1), m.group(2), m.group(3),
                float(m.group(4)) / a.t_end))


if __name__ == "__main__":
    main()
