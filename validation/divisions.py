#!/usr/bin/env python3
"""Which element division resolves the tips of planar extension: the same runs on the
axis-aligned cube and on the other divisions (mesh.division), for the default of
control::default_division (src/control/options.h). Writes each control file to
runs/validation/divisions/NAME.json, runs it with capflow (unless --reuse and it finished) and
prints the markdown table of docs/validation.md (section "divisions").

Usage: validation/divisions.py [--exe build/src/app/capflow] [--reuse] [--only NAME[,NAME...]]

Every figure comes from the run's run.log: the "end" line (t, wall, D, L, volume drift), the
first health warning and the failure, if any.
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table import ROOT, default_division, end_line, ensure_study_run, fmt_wall, study_args  # noqa: E402

OUT = os.path.join(ROOT, "runs", "validation", "divisions")

# name: (Ca, NE, NB, division, dt, t_end). Skalak C=1 from rest in planar extension.
#  * Ca=0.45, NB=8 to t=1: the tips form (the CI test PaperShort.TipResolutionGovernsVolume-
#    Conservation runs the NE=6 and NE=14 cubes and the turned cube);
#  * Ca=1.25, NB=10 to t=10: a strong flow, sharp tips (NE=14 reaches its steady state at t=20).
CASES = [
    ("q045_ne6_cube", 0.45, 6, 8, "cube", 2e-3, 1.0),
    ("q045_ne6_diagonal", 0.45, 6, 8, "diagonal", 2e-3, 1.0),
    ("q045_ne10_cube", 0.45, 10, 8, "cube", 2e-3, 1.0),
    ("q045_ne10_box", 0.45, 10, 8, "box", 2e-3, 1.0),
    ("q045_ne14_cube", 0.45, 14, 8, "cube", 2e-3, 1.0),
    ("q045_ne14_box", 0.45, 14, 8, "box", 2e-3, 1.0),
    ("s125_ne6_cube", 1.25, 6, 10, "cube", 2e-3, 10.0),
    ("s125_ne6_diagonal", 1.25, 6, 10, "diagonal", 2e-3, 10.0),
    ("s125_ne10_cube", 1.25, 10, 10, "cube", 2e-3, 10.0),
    ("s125_ne10_box", 1.25, 10, 10, "box", 2e-3, 10.0),
]


def control(name, ca, ne, nb, division, dt, t_end):
    return {
        "description": "Division study (validation/divisions.py): Skalak C=1, Ca=%g, NE=%d %s, NB=%d" % (
            ca, ne, division, nb),
        "capsule": {"law": "skalak", "C": 1},
        "mesh": {"elements": ne, "nb": nb, "division": division},
        "flow": {"type": "planar-extension"},
        "time": {"dt": dt, "t_end": t_end},
        "ca": ca,
        "output": {"dir": os.path.relpath(os.path.join(OUT, name), ROOT), "csv_every": 0.05},
        "numerics": {"threads": 1},
    }


def ensure_run(exe, name, cfg, reuse):
    return ensure_study_run(exe, OUT, name, cfg, reuse, "validation/divisions.py")


def health(rdir):
    """The first health warning and the failure of run.log, shortened to cause and time."""
    first, failure = "", ""
    with open(os.path.join(rdir, "run.log")) as f:
        for line in f:
            m = re.search(r"\] (warning|failure): (.*?) at t = ([0-9.]+)", line)
            if not m:
                continue
            text = "%s at t=%s" % (m.group(2), m.group(3))
            if m.group(1) == "warning" and not first:
                first = text
            if m.group(1) == "failure":
                failure = text
    return first, failure


def main():
    a = study_args(__doc__)
    only = a.only
    print("Skalak C=1 from rest, planar extension (`validation/divisions.py`; one thread per run):")
    print()
    print("| run | Ca | NE | division | NB, dt | reached | D | L | volume drift | first health warning | wall |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, ca, ne, nb, division, dt, t_end in CASES:
        if only and name not in only:
            continue
        rdir = ensure_run(a.exe, name, control(name, ca, ne, nb, division, dt, t_end), a.reuse)
        e = end_line(rdir)
        if e is None:
            print("| %s | %g | %d | %s | | no run (see %s.out) | | | | | |" % (name, ca, ne, division, rdir))
            continue
        warning, failure = health(rdir)
        reached = "t=%g" % e["t"] if e["reason"] == "t_end reached" else "**failed**: %s" % failure
        label = division + (" (default)" if default_division(ne, "planar-extension") == division else "")
        print("| %s | %g | %d | %s | %d, %g | %s | %.5f | %.5f | %.2e | %s | %s |" % (
            name, ca, ne, label, nb, dt, reached, e["D"], e["L"], e["drift"], warning or "none",
            fmt_wall(e["wall"])))


if __name__ == "__main__":
    main()
