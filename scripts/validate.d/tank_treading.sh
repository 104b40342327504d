# Red blood cells in simple shear against measured tank-treading frequencies (Fischer &
# Korzeniewski 2015; Tran-Son-Tay, Sutera & Rao 1984): lambda 0.35, 1 and 5, NE 6 NB 12 with a
# C, NB and NE check (about 45 minutes on the 2 cores). CAPFLOW_VALIDATE_REUSE=1 reuses the runs
# already made.
generators[tank_treading]="python3 validation/tank_treading.py ${CAPFLOW_VALIDATE_REUSE:+--reuse}"
