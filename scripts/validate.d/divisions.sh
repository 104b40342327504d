# Which element division resolves the tips of planar extension (the default of mesh.division):
# Skalak runs on the cube and the other divisions (about an hour on one core).
# CAPFLOW_VALIDATE_REUSE=1 reuses runs that already finished in runs/validation/divisions.
generators[divisions]="python3 validation/divisions.py ${CAPFLOW_VALIDATE_REUSE:+--reuse}"
