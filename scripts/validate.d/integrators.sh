# time.method "chebyshev" against "cash-karp" on the red cell in shear, NE 6 NB 10, to t = 1,
# against Cash-Karp at tolerance 1e-9 (about a minute on the 2 cores).
generators[integrators]="python3 validation/integrators.py"
