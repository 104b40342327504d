"""What the validation studies that run capflow share: their command line, and a run made from a
control dictionary in a run directory of its own."""
import argparse
import json
import os
import subprocess

from table import ROOT


def study_args(doc, reuse_help="reuse the runs already made"):
    """--exe, --reuse and --only (a set of run names, empty for all)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build/src/app/capflow"))
    ap.add_argument("--reuse", action="store_true", help=reuse_help)
    ap.add_argument("--only", default="", help="comma-separated run names")
    a = ap.parse_args()
    a.only = set(filter(None, a.only.split(",")))
    return a


def run_control(exe, command, rdir, cfg, extra=()):
    """Writes cfg to RDIR.json and runs `capflow COMMAND RDIR.json EXTRA --overwrite` from the
    repository root, its output in RDIR.out."""
    os.makedirs(os.path.dirname(rdir), exist_ok=True)
    with open(rdir + ".json", "w") as f:
        json.dump(cfg, f, indent=1)
    with open(rdir + ".out", "w") as log:
        subprocess.run([exe, command, rdir + ".json", *extra, "--overwrite"], stdout=log,
                       stderr=subprocess.STDOUT, cwd=ROOT, check=False)
