#!/usr/bin/env python3
"""Steady branches in planar extension with bending (Milestone 15): a Skalak capsule (C = 1,
lambda = 1) at NE = 6 (turned cube), NB = 10, by `capflow steady`'s pseudo-arclength
continuation from Ca = 0.01 (Eb = 0.01 and 0.001) and from Ca = 0.15 (Eb = 0, where a membrane
without bending stops being compressed), to Ca = 0.6, landing exactly on the table's Ca values
(the continuation's "at"); the small-deformation column is the theory of
tests/app/test_level_solver.cpp (SmallDeformationWithBendingMatchesLinearTheory), first order in
Ca. Prints the markdown table of docs/validation.md, section 19.4.

Usage: validation/bending_branches.py [--exe build/src/app/capflow] [--reuse]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table import ROOT  # noqa: E402

OUT = os.path.join(ROOT, "runs", "validation", "bending_branches")
BRANCHES = [("eb0.01", 0.01, 0.01), ("eb0.001", 0.001, 0.01), ("eb0", 0.0, 0.15)]
CAS = [0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.45, 0.6]


def control(name, eb, start):
    return {
        "description": "validation/bending_branches.py: Skalak C = 1, Eb = %g, planar extension" % eb,
        "capsule": {"law": "skalak", "C": 1, "bending": {"modulus": eb}},
        "mesh": {"elements": 6, "nb": 10, "division": "diagonal"},
        "flow": {"type": "planar-extension"},
        "ca": {"continuation": {"from": start, "to": 0.6, "step": 0.05,
                                "at": [c for c in CAS if c > start]}},
        "output": {"dir": os.path.relpath(os.path.join(OUT, name), ROOT), "png": False, "mp4": False},
    }


def run(exe, name, cfg, reuse):
    rdir = os.path.join(OUT, name)
    if reuse and os.path.exists(os.path.join(rdir, "steady.csv")):
        return rdir, None
    os.makedirs(OUT, exist_ok=True)
    path = rdir + ".json"
    with open(path, "w") as f:
        json.dump(cfg, f, indent=1)
    t0 = time.time()
    with open(rdir + ".out", "w") as log:
        subprocess.run([exe, "steady", path, "-o", rdir, "--overwrite"], stdout=log,
                       stderr=subprocess.STDOUT, cwd=ROOT, check=False)
    return rdir, time.time() - t0


def states(rdir):
    path = os.path.join(rdir, "steady.csv")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def at(rows, ca, key):
    for r in rows:
        if abs(r["ca"] - ca) <= 1e-9 * ca:
            return r[key]
    return None


def theory(ca, eb, ks=3.0):
    f2 = 24 * eb
    a = ca * (5 - 15 * f2 / 8) / (2 * ks + f2 * (2 + 3 * ks) / 4)
    return a * (0.5 + 0.75 * ks) + 15 * ca / 8


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build/src/app/capflow"))
    ap.add_argument("--reuse", action="store_true", help="reuse finished branches")
    a = ap.parse_args()
    result = {}
    for name, eb, start in BRANCHES:
        rdir, wall = run(a.exe, name, control(name, eb, start), a.reuse)
        result[name] = (states(rdir), wall)
    print("Skalak C = 1, planar extension, NE = 6 turned cube, NB = 10, `capflow steady` "
          "continuation to Ca = 0.6 (`validation/bending_branches.py`), states at the listed Ca; "
          "tau_min the most compressive principal tension:")
    print()
    print("| Ca | D, Eb = 0.01 (theory) | tau_min | D, Eb = 0.001 (theory) | tau_min | D, Eb = 0 | "
          "Eb = 0.01 vs 0 | Eb = 0.001 vs 0 |")
    print("|---|---|---|---|---|---|---|---|")
    r1, r2, r0 = (result[n][0] for n, _, _ in BRANCHES)
    for ca in CAS:
        d1, d2, d0 = at(r1, ca, "D"), at(r2, ca, "D"), at(r0, ca, "D")
        t1, t2 = at(r1, ca, "tau_min"), at(r2, ca, "tau_min")
        cell = lambda d, eb: "-" if d is None else ("%.5f (%.5f)" % (d, theory(ca, eb)) if ca <= 0.02
                                                      else "%.5f" % d)
        tau = lambda t: "-" if t is None else "%+.4f" % t
        rel = lambda d: "-" if d is None or d0 is None else "%+.2f %%" % (100 * (d / d0 - 1))
        print("| %g | %s | %s | %s | %s | %s | %s | %s |" % (
            ca, cell(d1, 0.01), tau(t1), cell(d2, 0.001), tau(t2),
            "-" if d0 is None else "%.5f" % d0, rel(d1), rel(d2)))
    print()
    for name, eb, start in BRANCHES:
        rows, wall = result[name]
        span = "Ca %.3g..%.3g" % (rows[0]["ca"], rows[-1]["ca"]) if rows else "no state"
        print("- Eb = %g: %d states, %s, %d velocity evaluations%s." % (
            eb, len(rows), span, sum(r["evaluations"] for r in rows),
            "" if wall is None else ", wall %.0f s" % wall))


if __name__ == "__main__":
    main()
