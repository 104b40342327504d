# Steady branches in planar extension with bending Eb = 0.01 and 0.001 from Ca = 0.01, and the
# branch without bending from Ca = 0.15, to Ca = 0.6 (NE 6 NB 10; a few minutes on the 2 cores).
# CAPFLOW_VALIDATE_REUSE=1 reuses finished branches.
generators[bending_branches]="python3 validation/bending_branches.py ${CAPFLOW_VALIDATE_REUSE:+--reuse}"
