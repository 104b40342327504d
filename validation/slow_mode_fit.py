#!/usr/bin/env python3
"""Fits y(t) = y_inf + c exp(-(t - t_end)/tau) to columns of a run's timeseries.csv over
T0 <= t (<= T1 if given; t_end is the last time fitted) (least squares in y_inf and c for each
tau on a grid: 0.01 steps up to 1, then 0.1 steps), and prints, per column,
the asymptote y_inf, tau, the last value, the rate dy/dt at the end, the rms misfit and the time
at which |dy/dt| would fall below the steady tolerance (1e-4 per unit time) if the one mode
goes on. Used for the neo-Hookean Ca=0.4 notes of docs/validation.md and for the shear states
before the wrinkles grow (T0:T1 ends the fit where the health monitor first warns).

Usage: validation/slow_mode_fit.py RUN_DIR T0[:T1] [COLUMN ...]   (default columns L S W Lc
edge_curvature tau_max)
"""
import csv
import math
import os
import sys

# The relaxation times tried: 0.01 steps up to 1, then 0.1 steps up to 200.9.
TAUS = [0.01 * k for k in range(1, 100)] + [1 + 0.1 * k for k in range(0, 2000)]


def fit(t, y, taus):
    n, te = len(y), t[-1]
    sy = sum(y)
    best = None
    for tau in taus:
        e = [math.exp(-(ti - te) / tau) for ti in t]
        se, see = sum(e), sum(x * x for x in e)
        sey = sum(a * b for a, b in zip(e, y))
        det = n * see - se * se
        c0, c1 = (see * sy - se * sey) / det, (n * sey - se * sy) / det
        r = sum((c0 + c1 * a - b) ** 2 for a, b in zip(e, y))
        if best is None or r < best[0]:
            best = (r, tau, c0, c1)
    return best


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    rdir, span = sys.argv[1], sys.argv[2].split(":")
    t0, t1 = float(span[0]), float(span[1]) if len(span) > 1 else math.inf
    cols = sys.argv[3:] or ["L", "S", "W", "Lc", "edge_curvature", "tau_max"]
    with open(os.path.join(rdir, "timeseries.csv")) as f:
        rows = [r for r in csv.DictReader(f) if t0 <= float(r["t"]) <= t1]
    if len(rows) < 5:
        sys.exit("slow_mode_fit.py: fewer than 5 rows with %g <= t <= %g in %s" % (t0, t1, rdir))
    t = [float(r["t"]) for r in rows]
    print("fit over t = %.3f .. %.3f (%d rows)" % (t[0], t[-1], len(t)))
    for col in cols:
        if col not in rows[0]:
            sys.exit("slow_mode_fit.py: no column %r in timeseries.csv" % col)
        y = [float(r[col]) for r in rows]
        r, tau, c0, c1 = fit(t, y, TAUS)
        rate = -c1 / tau
        t_quiet = t[-1] + (tau * math.log(abs(rate) / 1e-4) if abs(rate) > 1e-4 else 0.0)
        edge = " (tau at the end of the grid)" if tau >= TAUS[-1] - 1e-9 or tau <= TAUS[0] + 1e-9 else ""
        print("%-15s asymptote %.5f  tau %6.1f%s  last %.5f  rate %+.2e per unit time  rms %.0e  "
              "|rate| < 1e-4 from t ~ %.0f" % (col, c0, tau, edge, y[-1], rate, math.sqrt(r / len(y)), t_quiet))


if __name__ == "__main__":
    main()
