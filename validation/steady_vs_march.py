#!/usr/bin/env python3
"""capflow steady against the time march: the steady states of a branch at chosen levels of Ca.

For each Ca in --ca, runs `capflow run` from rest on the branch's control file (same law, mesh,
flow) at that constant Ca with adaptive steps until the steady test fires with a tight rate
tolerance (steady.tolerance, default 1e-6 per unit time) and the volume held at the sphere's
(numerics.volume_correction, as capflow steady holds it), and compares D, L, S, W with the row of
the branch's steady.csv at that Ca (capflow steady, run before: `capflow steady CONTROL -o DIR`).
Prints a markdown table; exits 1 when a difference exceeds --limit (default 1e-4).

  validation/steady_vs_march.py CONTROL.json BRANCH_DIR --ca 0.45,0.6,1.25
      [--capflow build/src/app/capflow] [--rate 1e-6] [--t-end 60] [--limit 1e-4]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("control")
    ap.add_argument("branch")
    ap.add_argument("--ca", required=True)
    ap.add_argument("--capflow", default="build/src/app/capflow")
    ap.add_argument("--rate", type=float, default=1e-6)
    ap.add_argument("--t-end", type=float, default=60.0)
    ap.add_argument("--limit", type=float, default=1e-4)
    a = ap.parse_args()
    base = json.load(open(a.control))
    rows = list(csv.DictReader(open(os.path.join(a.branch, "steady.csv"))))
    print("| Ca | capflow steady D, L, S, W | march D, L, S, W (steady test at t) | largest difference |")
    print("|---|---|---|---|")
    worst = 0.0
    with tempfile.TemporaryDirectory() as work:
        for ca in [float(c) for c in a.ca.split(",")]:
            row = next((r for r in rows if abs(float(r["ca"]) - ca) < 1e-9), None)
            if row is None:
                sys.exit("no steady state at Ca = %g in %s" % (ca, a.branch))
            c = json.loads(json.dumps(base))
            c["ca"] = ca
            c["time"] = {"dt": "auto", "t_end": a.t_end}
            c["steady"] = {"stop": True, "tolerance": a.rate, "window": 1.0, "min_hold": 1.0}
            c["output"] = {"csv_every": 0.5, "mp4": False}
            # The volume held at the sphere's, as capflow steady holds it (paper eq. 23): without
            # it the discretisation's slow volume leak keeps the march moving.
            c.setdefault("numerics", {})["volume_correction"] = True
            path = os.path.join(work, "march.json")
            json.dump(c, open(path, "w"))
            out = os.path.join(work, "march_%g" % ca)
            p = subprocess.run([a.capflow, "run", path, "-o", out], capture_output=True, text=True)
            if p.returncode != 0:
                sys.exit("capflow run failed at Ca = %g:\n%s" % (ca, p.stderr[-2000:]))
            st = list(csv.DictReader(open(os.path.join(out, "steady.csv"))))
            if not st:
                print("| %g | - | no steady state by t = %g | - |" % (ca, a.t_end))
                worst = float("inf")
                continue
            m = st[-1]
            d = max(abs(float(row[k]) - float(m[k])) for k in ("D", "L", "S", "W"))
            worst = max(worst, d)
            fmt = lambda r: ", ".join("%.6f" % float(r[k]) for k in ("D", "L", "S", "W"))
            print("| %g | %s | %s (t = %.1f) | %.1e |" % (ca, fmt(row), fmt(m), float(m["t"]), d))
    print("\nlargest difference %.1e (limit %g): %s" % (worst, a.limit,
                                                       "met" if worst <= a.limit else "NOT met"))
    return 0 if worst <= a.limit else 1


if __name__ == "__main__":
    sys.exit(main())
