#!/usr/bin/env python3
"""Fits the stability limit of fixed RK4 steps to the rows of stability_limits.sh:

    h* = c(NE, division) * dx_min^p * Ca / (1 + b Ca)

(c per mesh family; p, b common), least squares in log h* (b by a scan), separately for the
rows at the sphere (both laws) and at the Skalak steady states. Prints the constants and each
row's measured / fitted ratio; the neo-Hookean steady rows against the sphere's fit.
Usage: benchmarks/capsule/stability_limits.sh BUILD | benchmarks/capsule/fit_stability.py
"""
import math
import re
import sys


rows = []
for line in sys.stdin:
    m = re.match(r"(\S+)\s+NE=(\d+)\s+(\S+)\s+NB=(\d+)\s+Ca=(\S+)\s+(\S+)\s+dx_min (\S+)\s+h\* (\S+)",
                 line)
    if m:
        law, ne, div, nb, ca, state, dx, h = m.groups()
        rows.append((law, int(ne), div, int(nb), float(ca), float(dx), float(h), state))
all_rows = rows


def design(rows, b):
    a, y = [], []
    for law, ne, div, nb, ca, dx, h, state in rows:
        v = [1.0 if (ne, div) == f else 0.0 for f in families]
        v.append(math.log(dx))
        a.append(v)
        y.append(math.log(h) - math.log(ca / (1 + b * ca)))
    return a, y


def lstsq(a, y):
    """Least squares by the normal equations (a few unknowns), Gauss-Jordan with pivoting."""
    n = len(a[0])
    m = [[sum(r[i] * r[j] for r in a) for j in range(n)] + [sum(r[i] * v for r, v in zip(a, y))]
         for i in range(n)]
    for c in range(n):
        piv = max(range(c, n), key=lambda k: abs(m[k][c]))
        m[c], m[piv] = m[piv], m[c]
        for k in range(n):
            if k != c:
                f = m[k][c] / m[c][c]
                m[k] = [u - f * w for u, w in zip(m[k], m[c])]
    x = [m[i][n] / m[i][i] for i in range(n)]
    res = sum((sum(ri * xi for ri, xi in zip(r, x)) - v) ** 2 for r, v in zip(a, y))
    return x, res


def fit(rows):
    best = None
    for k in range(501):
        b = 0.01 * k
        x, r = lstsq(*design(rows, b))
        if best is None or r < best[0]:
            best = (r, b, x)
    return best


def predict(x, b, row):
    law, ne, div, nb, ca, dx, h, state = row
    return math.exp(x[families.index((ne, div))] + x[-1] * math.log(dx)) * ca / (1 + b * ca)


for title, chosen, others in (
        ("at the sphere", [r for r in all_rows if r[7] == "sphere"], []),
        ("at the Skalak steady states",
         [r for r in all_rows if r[7] != "sphere" and r[0] == "skalak"], []),
        ("the neo-Hookean steady states against the sphere's fit", [],
         [r for r in all_rows if r[7] != "sphere" and r[0] != "skalak"])):
    if chosen:
        families = sorted({(r[1], r[2]) for r in chosen})
        r, b, x = fit(chosen)
        print(f"## {title}: p = {x[-1]:.3f}, b = {b:.2f}, rms log residual "
              f"{math.sqrt(r / len(chosen)):.3f}")
        print("  " + ", ".join(f"c(NE={ne}, {div}) = {math.exp(x[i]):.4f}"
                               for i, (ne, div) in enumerate(families)))
    else:
        print(f"## {title}")
    for row in chosen + others:
        hf = predict(x, b, row)
        law, ne, div, nb, ca, dx, h, state = row
        print(f"{law:12s} NE={ne:<2d} {div:8s} NB={nb:<2d} Ca={ca:<5g} h* {h:.5f} fit {hf:.5f} "
              f"ratio {h / hf:.3f}")
