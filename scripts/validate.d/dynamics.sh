# Milestone 3 paper reproduction (long: hours on 2 cores). The capflow runs of validation/*.json
# and their tables; CAPFLOW_VALIDATE_REUSE=1 reuses runs that already finished in runs/validation.
generators[dynamics]="python3 validation/table.py ${CAPFLOW_VALIDATE_REUSE:+--reuse}"
