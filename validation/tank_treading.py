#!/usr/bin/env python3
"""Red blood cells in simple shear against measured tank-treading frequencies (Milestone 15).

The cell: Evans-Fung biconcave (reduced volume 0.64), symmetry axis along the flow, Skalak
C = 10 (or 50), bending Eb = 5e-3 about its own shape, Runge-Kutta-Chebyshev steps, NE 6 NB 12
(one run at NB 14, one at NE 10). Each run goes from rest to t_end; `capflow figure` measures
the duration T of the last full turn of a membrane point about the centroid (ts_tank_treading),
f = 1 / T; a run that fails or makes no full turn gets the point's mean turning rate. Over
that turn the script reads the inclination and D from timeseries.csv: a cell whose inclination
stays above -45 degrees tank-treads (swinging by the inclination's range); one that turns past
-90 degrees tumbles.

The measurements (f / G, cycles per unit strain; 4 pi f / G is 1 for a rigid sphere's G / 2):
- Fischer & Korzeniewski (2015, Biophys. J. 108:1352, figure S11), suspending viscosity
  28.9 mPa s: 225 cells, the per-cell data distributed with the tRBC-UQ study
  (github.com/cselab/tRBC-UQ, validation/rbc_shear_flow/exp/TTF/data_donors12.csv, "TTF is
  dimensionless (TTF/shear rate)"); below, the means per shear-rate group.
- Tran-Son-Tay, Sutera & Rao (1984, Biophys. J. 46:65, table I), suspending viscosity 35 cP,
  young cells (cytoplasm 10 cP), the angular frequency omega in rad/s: f / G = omega / (2 pi G).
A shear rate G maps to Ca = eta_o G a / Gs with a = 2.82 um (the radius of the sphere of the
cell's volume, 94 um^3) and Gs = 5 uN/m (the shear modulus; published values 2.5-6 uN/m, so Ca
is known to a factor of about 2, along which the measured f / G changes by under 20 %). The
viscosity ratio of the measurements is 10 / 28.9 = 0.35 and 10 / 35 = 0.29 (cytoplasm 10 mPa s
at room temperature); the runs use 0.35.

Prints the markdown table of docs/validation.md, section 19.7. About 45 minutes on 2 cores.

Usage: validation/tank_treading.py [--exe build/src/app/capflow] [--reuse] [--only NAME,...]
"""
import csv
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table import ROOT, end_line, ensure_study_run, fmt_wall, study_args  # noqa: E402

OUT = os.path.join(ROOT, "runs", "validation", "tank_treading")

# name, lambda, Ca, C, (NE, NB), t_end
RUNS = [
    ("l0.35_ca0.25", 0.35, 0.25, 10, (6, 12), 50),
    ("l0.35_ca1", 0.35, 1.0, 10, (6, 12), 40),
    ("l0.35_ca0.5", 0.35, 0.5, 10, (6, 12), 45),
    ("l0.35_ca2", 0.35, 2.0, 10, (6, 12), 40),
    ("l1_ca1", 1.0, 1.0, 10, (6, 12), 40),
    ("l5_ca1", 5.0, 1.0, 10, (6, 12), 40),
    ("l5_ca2", 5.0, 2.0, 10, (6, 12), 40),
    ("l0.35_ca1_c50", 0.35, 1.0, 50, (6, 12), 40),
    ("l0.35_ca1_nb14", 0.35, 1.0, 10, (6, 14), 40),
    ("l5_ca1_ne10", 5.0, 1.0, 10, (10, 12), 40),
]

A_UM, GS = 2.82e-6, 5e-6
# (suspending viscosity Pa s, [(G 1/s, f / G)])
FISCHER_2015 = (0.0289, [(8.2, 0.0398), (16.9, 0.0368), (32.4, 0.0330), (65.2, 0.0287),
                         (131.6, 0.0260), (258.0, 0.0254)])
TRAN_SON_TAY_1984 = (0.035, [(28.6, 6.22 / (2 * math.pi * 28.6)), (42.9, 9.42 / (2 * math.pi * 42.9)),
                             (57.1, 12.7 / (2 * math.pi * 57.1)), (114.3, 24.6 / (2 * math.pi * 114.3)),
                             (171.4, 37.4 / (2 * math.pi * 171.4))])


def measured(series, ca):
    """f / G of a measurement series at Ca (log-linear in G between its points), None outside."""
    eta, rows = series
    g = ca * GS / (eta * A_UM)
    for (g0, f0), (g1, f1) in zip(rows, rows[1:]):
        if g0 <= g <= g1:
            w = math.log(g / g0) / math.log(g1 / g0)
            return f0 + w * (f1 - f0)
    return None


def control(name, lam, ca, c, mesh, t_end):
    return {
        "description": "validation/tank_treading.py: red cell in shear, lambda %g, Ca %g, C %g" % (lam, ca, c),
        "capsule": {"law": "skalak", "C": c, "shape": {"biconcave": {"axis": "x"}},
                    "bending": {"modulus": 0.005, "model": "reference"}, "viscosity_ratio": lam},
        "mesh": {"elements": mesh[0], "nb": mesh[1]}, "flow": {"type": "simple-shear"}, "ca": ca,
        "time": {"t_end": t_end, "method": "chebyshev"},
        "output": {"dir": os.path.relpath(os.path.join(OUT, name), ROOT), "csv_every": 0.1,
                   "png": False, "mp4": False, "vtk_every": 0.25, "vtk_points": 6},
    }


def last_turn(exe, rdir):
    """(start, T) of the membrane point's last full turn, from capflow figure's note, or the
    mean turning rate (deg per unit G t) when it has made no full turn."""
    fig = os.path.join(rdir, "figures")
    subprocess.run([exe, "figure", rdir, "-o", fig, "--kinds", "timeseries", "--no-gnuplot"],
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT, check=False)
    md = os.path.join(fig, "figures.md")
    text = open(md).read() if os.path.exists(md) else ""
    m = re.search(r"last full turn, from t = ([0-9.e+-]+), took T G = ([0-9.e+-]+)", text)
    if m:
        return float(m.group(1)), float(m.group(2))
    m = re.search(r"turns at ([0-9.e+-]+) deg per unit G t", text)
    return float(m.group(1)) if m else None


def over(rdir, start, key):
    with open(os.path.join(rdir, "timeseries.csv")) as f:
        vals = [float(r[key]) for r in csv.DictReader(f) if float(r["t"]) >= start]
    return min(vals), max(vals)


def main():
    a = study_args(__doc__, "reuse the runs already made (finished or failed)")
    print("| run | lambda | Ca | C | NE NB | state over the last turn | T G | f / G | 4 pi f / G "
          "| Fischer 2015 f / G | Tran-Son-Tay 1984 f / G | wall |")
    print("|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|")
    for spec in RUNS:
        name, lam, ca, c, mesh, _ = spec
        if a.only and name not in a.only:
            continue
        rdir = ensure_study_run(a.exe, OUT, name, control(*spec), a.reuse, "validation/tank_treading.py")
        e = end_line(rdir)
        if e is None:
            print("| %s | %g | %g | %g | %d %d | no run (see %s.out) | | | | | | |" % (
                name, lam, ca, c, mesh[0], mesh[1], rdir))
            continue
        ref = [measured(s, ca) for s in (FISCHER_2015, TRAN_SON_TAY_1984)]
        turn = last_turn(a.exe, rdir) if os.path.exists(os.path.join(rdir, "surface.pvd")) else None
        failed = "" if e["reason"] == "t_end reached" else "failed at t = %g; " % e["t"]
        if turn is None or isinstance(turn, float):
            rate = "" if turn is None else ", mean turning %.1f deg per G t" % turn
            state, cols = failed + "no full turn" + rate, ["-", "-", "-"]
        else:
            start, period = turn
            i0, i1 = over(rdir, start, "inclination_deg")
            d0, d1 = over(rdir, start, "D")
            kind = "tumbling" if i0 < -45 else "tank-treading"
            state = failed + "%s: inclination %.1f to %.1f deg, D %.3f to %.3f" % (kind, i0, i1, d0, d1)
            f = 1 / period
            cols = ["%.2f" % period, "%.4f" % f, "%.3f" % (4 * math.pi * f)]
            ref = ["%.4f (x %.2f)" % (r, f / r) if r else "-" for r in ref]
        ref = [r if isinstance(r, str) else "-" for r in ref]
        print("| %s | %g | %g | %g | %d %d | %s | %s | %s | %s |" % (
            name, lam, ca, c, mesh[0], mesh[1], state, " | ".join(cols), " | ".join(ref),
            fmt_wall(e["wall"])), flush=True)


if __name__ == "__main__":
    main()
