#!/usr/bin/env python3
"""Adaptive against fixed time steps on one run (Milestone 8 benchmark).

Runs capflow on a control file (default: Skalak C=1, Ca=0.45, planar extension, NE=6 diagonal,
NB=10, from rest) once per setting and prints a markdown table: wall time, steps, rejected steps,
velocity evaluations, and the differences of D, L, S, W and the volume from a reference run with
a small fixed step (all runs end at the same t_end, so the states are compared at one time).
With --steady every run also stops at the steady state (steady.stop) and the table gives the
time it fired, and `capflow steady` solves for the same state (one more row: its wall time,
velocity evaluations, and D, L, S, W against the reference march's final state); wall times are
medians over --repeat runs, the settings alternated.

  benchmarks/capsule/time_stepping.py [--capflow build/src/app/capflow] [--t-end 3]
      [--reference 1e-3] [--settings auto:1e-6,fixed:8e-3] [--steady] [--repeat 3]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

BASE = {
    "description": "time stepping benchmark",
    "capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 10, "division": "diagonal"},
    "flow": {"type": "planar-extension"},
    "ca": 0.45,
    "output": {"csv_every": 0.1, "mp4": False},
}


def run(capflow, control, workdir, name):
    path = os.path.join(workdir, name + ".json")
    with open(path, "w") as f:
        json.dump(control, f)
    out = os.path.join(workdir, name)
    p = subprocess.run([capflow, "run", path, "-o", out, "--overwrite"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        sys.exit("capflow failed for %s:\n%s" % (name, p.stderr[-2000:]))
    end = [json.loads(l) for l in open(os.path.join(out, "events.jsonl"))
           if '"event":"end"' in l.replace(" ", "")][-1]
    rows = list(csv.DictReader(open(os.path.join(out, "timeseries.csv"))))
    return end, rows[-1]


def solve(capflow, control, workdir):
    path = os.path.join(workdir, "steady.json")
    with open(path, "w") as f:
        json.dump(control, f)
    out = os.path.join(workdir, "steady")
    p = subprocess.run([capflow, "steady", path, "-o", out, "--overwrite"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        sys.exit("capflow steady failed:\n%s" % p.stderr[-2000:])
    end = [json.loads(l) for l in open(os.path.join(out, "events.jsonl"))
           if '"event":"end"' in l.replace(" ", "")][-1]
    return end, list(csv.DictReader(open(os.path.join(out, "steady.csv"))))[-1]


def setting(s):
    kind, value = s.split(":")
    if kind == "auto":
        return {"dt": "auto", "tolerance": float(value)}, "auto, tolerance " + value
    return {"dt": float(value)}, "fixed dt = " + value


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--capflow", default="build/src/app/capflow")
    ap.add_argument("--control", help="base control file (default: the Skalak case above)")
    ap.add_argument("--t-end", type=float, default=3.0)
    ap.add_argument("--reference", type=float, default=1e-3, help="the reference's fixed dt")
    ap.add_argument("--settings", default="auto:1e-6,fixed:8e-3")
    ap.add_argument("--steady", action="store_true", help="stop at the steady state")
    ap.add_argument("--repeat", type=int, default=1)
    a = ap.parse_args()
    base = json.load(open(a.control)) if a.control else BASE
    base = json.loads(json.dumps(base))
    base.setdefault("steady", {})["stop"] = a.steady
    base.setdefault("output", {})["mp4"] = False
    base["output"].pop("dir", None)
    settings = [("fixed:%g" % a.reference, True)] + [(s, False) for s in a.settings.split(",")]
    results = {}
    with tempfile.TemporaryDirectory() as work:
        for rep in range(a.repeat):
            for s, _ in settings:
                time, _label = setting(s)
                c = json.loads(json.dumps(base))
                c["time"] = dict(time, t_end=a.t_end)
                end, last = run(a.capflow, c, work, "run_%d" % len(results.get(s, [])))
                results.setdefault(s, []).append((end, last))
            if a.steady:
                results.setdefault("steady", []).append(solve(a.capflow, base, work))
    ref_end, ref = results[settings[0][0]][0]
    print("| run (t_end %g%s) | wall s (median of %d) | t of the last row | steps | rejected | velocity evaluations "
          "| D | dD | dL | dS | dW | d(volume) |" % (a.t_end, ", steady.stop" if a.steady else "", a.repeat))
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    worst = 0.0
    for s, is_ref in settings:
        runs = results[s]
        end, last = runs[0]
        wall = statistics.median(r[0]["wall_s"] for r in runs)
        diffs = [abs(float(last[k]) - float(ref[k])) for k in ("D", "L", "S", "W", "volume")]
        if not is_ref and s.startswith("auto"):
            worst = max(worst, max(diffs))
        label = setting(s)[1] + (" (reference)" if is_ref else "")
        print("| %s | %.1f | %s | %d | %d | %d | %.8f | %s |" % (
            label, wall, last["t"], end["steps"], end.get("rejected_steps", 0),
            end["velocity_evaluations"], float(last["D"]),
            " | ".join("%.1e" % d for d in diffs)))
    if a.steady:
        runs = results["steady"]
        end, row = runs[0]
        wall = statistics.median(r[0]["wall_s"] for r in runs)
        diffs = [abs(float(row[k]) - float(ref[k])) for k in ("D", "L", "S", "W")]
        print("| capflow steady (residual %s) | %.1f | - | - | - | %d | %.8f | %s | - |" % (
            row["residual"], wall, end["velocity_evaluations"], float(row["D"]),
            " | ".join("%.1e" % d for d in diffs)))
        print("\n(with steady.stop the runs end at different times: the differences are at "
              "different t when the steady test fires at different steps)")
    else:
        print("\nlargest difference of an auto run from the reference: %.2e" % worst)


if __name__ == "__main__":
    main()
