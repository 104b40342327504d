#!/usr/bin/env python3
"""Simple shear of a neo-Hookean capsule below Ca ~0.15: the tank-treading state before the
wrinkles grow. At low Ca the membrane carries compressive tensions (tau_min < 0); without
bending stiffness it wrinkles at the grid scale (the health monitor's "node-to-node
oscillation growing" warning), later on a finer grid, and the shape then fluctuates about a
larger D. The state the capsule relaxes to before that is the answer the small-deformation
theory (D = 25/12 Ca, 45 degrees to first order) and smooth-membrane computations describe.

For each case: run NE=6 from rest (one thread, two runs at a time), take t_w = the first
oscillation warning of events.jsonl (t_end if none), fit D(t) and the inclination to
y_inf + c exp(-(t - t_w)/tau) over [0.4 t_w, t_w] (validation/slow_mode_fit.py's fit) and print
the markdown table of docs/validation.md ("Simple shear below Ca = 0.15").

Usage: validation/shear_wrinkles.py [--exe build/src/app/capflow] [--reuse] [--only NAME,...]
                                    [--jobs 2]
"""
import argparse
import concurrent.futures
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from slow_mode_fit import TAUS, fit  # noqa: E402
from table import ROOT, end_line, ensure_study_run, fmt_wall, series  # noqa: E402

OUT = os.path.join(ROOT, "runs", "validation", "shear_wrinkles")

# name: (Ca, NB, dt, t_end); NE=6 (the cube, the simple-shear default), neo-Hookean, lambda=1.
CASES = [
    ("ca00375_nb8", 0.0375, 8, 5e-4, 2.0),
    ("ca00375_nb10", 0.0375, 10, 5e-4, 2.0),
    ("ca0075_nb8", 0.075, 8, 1e-3, 3.0),
    ("ca0075_nb10", 0.075, 10, 1e-3, 3.0),
    ("ca015_nb8", 0.15, 8, 2e-3, 6.0),
    ("ca015_nb10", 0.15, 10, 2e-3, 6.0),
]


def control(name, ca, nb, dt, t_end):
    return {
        "description": "Shear below Ca=0.15 (validation/shear_wrinkles.py): neo-Hookean, Ca=%g, NE=6 NB=%d"
                       % (ca, nb),
        "capsule": {"law": "neo-hookean"},
        "mesh": {"elements": 6, "nb": nb},
        "flow": {"type": "simple-shear"},
        "time": {"dt": dt, "t_end": t_end},
        "ca": ca,
        "output": {"dir": os.path.relpath(os.path.join(OUT, name), ROOT), "csv_every": 0.02},
        "numerics": {"threads": 1},
    }


def ensure_run(exe, name, cfg, reuse):
    return ensure_study_run(exe, OUT, name, cfg, reuse, "validation/shear_wrinkles.py")


def first_oscillation(rdir):
    """t of the first node-to-node oscillation warning or failure, None if there is none."""
    with open(os.path.join(rdir, "events.jsonl")) as f:
        for line in f:
            ev = json.loads(line)
            if ev.get("event") in ("warning", "failure") and ev.get("cause") == "oscillation":
                return float(ev["t"])
    return None


def analyse(rdir, t_end):
    rows = series(rdir)
    t_w = first_oscillation(rdir)
    t1 = t_w if t_w is not None else rows[-1]["t"]
    win = [r for r in rows if 0.4 * t1 <= r["t"] <= t1]
    t = [r["t"] for r in win]
    out = {"t_w": t_w, "t1": t1, "t0": t[0]}
    for col in ("D", "inclination_deg"):
        y = [r[col] for r in win]
        _, tau, c0, c1 = fit(t, y, TAUS)
        out[col] = (c0, tau, y[-1])
    late = [r for r in rows if r["t"] >= rows[-1]["t"] - 1.0]
    out["late_D"] = sum(r["D"] for r in late) / len(late)
    out["late_t"] = (late[0]["t"], late[-1]["t"])
    out["tau_min"] = win[-1]["tau_min"]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build/src/app/capflow"))
    ap.add_argument("--reuse", action="store_true", help="reuse finished runs in their run directories")
    ap.add_argument("--only", default="", help="comma-separated run names")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time (one thread each)")
    a = ap.parse_args()
    only = set(filter(None, a.only.split(",")))
    cases = [c for c in CASES if not only or c[0] in only]
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        dirs = list(pool.map(lambda c: ensure_run(a.exe, c[0], control(*c), a.reuse), cases))
    print("Neo-Hookean, simple shear, lambda = 1, NE=6, from rest (`validation/shear_wrinkles.py`; "
          "one thread per run, two at a time). Fit window [0.4 t_w, t_w], t_w = first "
          "oscillation warning; small-deformation theory D = 25/12 Ca:")
    print()
    print("| run | Ca | NB, dt | t_w (oscillation) | D fitted (tau) | D at t_w | theory 25/12 Ca | "
          "inclination fitted (tau) | tau_min at t_w | D, mean of the last time unit | wall |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (name, ca, nb, dt, t_end), rdir in zip(cases, dirs):
        e = end_line(rdir)
        if e is None:
            print("| %s | %g | %d, %g | no run (see %s.out) | | | | | | | |" % (name, ca, nb, dt, rdir))
            continue
        r = analyse(rdir, t_end)
        tw = "%.3f" % r["t_w"] if r["t_w"] is not None else "none by t=%g" % e["t"]
        d, inc = r["D"], r["inclination_deg"]
        print("| %s | %g | %d, %g | %s | %.5f (%.2f) | %.5f | %.5f | %.2f (%.2f) | %.4f | %.5f (t=%.1f..%.1f) "
              "| %s |" % (name, ca, nb, dt, tw, d[0], d[1], d[2], 25.0 / 12.0 * ca, inc[0], inc[1],
                          r["tau_min"], r["late_D"], r["late_t"][0], r["late_t"][1], fmt_wall(e["wall"])))


if __name__ == "__main__":
    main()
