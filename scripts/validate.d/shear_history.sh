# Neo-Hookean simple shear at Ca = 0.3 and 0.6 from rest: D(t) at three resolutions beside the
# published histories, and with doubled quadrature and a tighter step tolerance (about 3.5 minutes
# on the 2 cores). CAPFLOW_VALIDATE_REUSE=1 reuses finished runs.
generators[shear_history]="python3 validation/shear_history.py ${CAPFLOW_VALIDATE_REUSE:+--reuse}"
