#!/usr/bin/env python3
"""Cash-Karp against Runge-Kutta-Chebyshev steps (time.method) on a stiff membrane: the red blood
cell in shear (Evans-Fung, axis along the flow, Skalak C = 10, Eb = 5e-3 about its own shape,
Ca = 0.1, lambda = 1) from rest, capflow run's adaptive steps at the default tolerance on 2
threads. For each mesh the two methods run one after the other (alternating which goes first
from mesh to mesh), to its own end time each (Cash-Karp is slow: --ck-t-end). Prints a markdown
table: steps (rejected), velocity evaluations, the wall time per G t over the second half of
each run (from timeseries.csv, after the start-up transient), D at the common end time,
and the ratio of the wall rates.

  benchmarks/capsule/stiff_steps.py [--capflow build/src/app/capflow]
      [--meshes 6:10,6:12,10:12] [--ck-t-end 0.5] [--rkc-t-end 1.0]
"""
import argparse
import csv
import json
import os
import re
import subprocess
import tempfile


def control(ne, nb, method, t_end, out):
    return {"capsule": {"law": "skalak", "C": 10, "shape": {"biconcave": {"axis": "x"}},
                        "bending": {"modulus": 0.005, "model": "reference"}},
            "mesh": {"elements": ne, "nb": nb}, "flow": {"type": "simple-shear"}, "ca": 0.1,
            "time": {"t_end": t_end, "method": method},
            "output": {"dir": out, "csv_every": 0.05, "png": False, "mp4": False}}


def run(capflow, tmp, ne, nb, method, t_end):
    out = os.path.join(tmp, "ne%d_nb%d_%s" % (ne, nb, method))
    path = out + ".json"
    with open(path, "w") as f:
        json.dump(control(ne, nb, method, t_end, out), f)
    r = subprocess.run([capflow, "run", path], capture_output=True, text=True)
    end = [l for l in r.stdout.splitlines() + r.stderr.splitlines() if l.startswith("end")]
    if not end:
        raise RuntimeError("%s NE %d NB %d failed: %s" % (method, ne, nb, (r.stderr or r.stdout)[-300:]))
    m = re.search(r"steps=(\d+) \(rejected (\d+)\) velocity evaluations=(\d+) wall=([0-9.]+) s", end[-1])
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    half = [x for x in rows if float(x["t"]) >= t_end / 2 - 1e-9]
    a, b = half[0], half[-1]
    span = float(b["t"]) - float(a["t"])
    evals, wall = int(m.group(3)), float(m.group(4))
    return {"steps": m.group(1), "rejected": m.group(2), "evals": evals,
            "wall_rate": (float(b["wall_s"]) - float(a["wall_s"])) / span,
            "D": {round(float(x["t"]), 6): float(x["D"]) for x in rows}}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--capflow", default="build/src/app/capflow")
    ap.add_argument("--meshes", default="6:10,6:12,10:12")
    ap.add_argument("--ck-t-end", type=float, default=0.5)
    ap.add_argument("--rkc-t-end", type=float, default=1.0)
    a = ap.parse_args()
    print("| NE NB | method | to t | steps (rejected) | velocity evaluations | wall per G t "
          "(second half) | D at t = %g | wall ratio |" % a.ck_t_end)
    print("|---|---|---:|---|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for k, mesh in enumerate(a.meshes.split(",")):
            ne, nb = (int(v) for v in mesh.split(":"))
            order = [("cash-karp", a.ck_t_end), ("chebyshev", a.rkc_t_end)]
            if k % 2:
                order.reverse()
            res = {m: run(a.capflow, tmp, ne, nb, m, t) for m, t in order}
            ck, rkc = res["cash-karp"], res["chebyshev"]
            t = round(a.ck_t_end, 6)
            for m, t_end in (("cash-karp", a.ck_t_end), ("chebyshev", a.rkc_t_end)):
                r = res[m]
                print("| %d %d | %s | %g | %s (%s) | %d | %.1f s | %.6f | %s |" % (
                    ne, nb, m, t_end, r["steps"], r["rejected"], r["evals"], r["wall_rate"], r["D"][t],
                    "%.1fx" % (ck["wall_rate"] / rkc["wall_rate"]) if m == "chebyshev" else ""))


if __name__ == "__main__":
    main()
