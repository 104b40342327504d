# Simple shear below Ca ~0.15: the tank-treading state before the wrinkles grow (neo-Hookean,
# Ca = 0.0375, 0.075, 0.15 at NB = 8 and 10, fitted up to the first oscillation warning;
# about 8 minutes on the 2 cores). CAPFLOW_VALIDATE_REUSE=1 reuses finished runs.
generators[shear_wrinkles]="python3 validation/shear_wrinkles.py ${CAPFLOW_VALIDATE_REUSE:+--reuse}"
