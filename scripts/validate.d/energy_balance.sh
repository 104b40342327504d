# The energy balance of neo-Hookean simple shear at Ca = 0.6 through the overshoot at NB = 8 to 14
# (about 4 minutes on the 2 cores; ctest runs NB = 8 and 10).
generators[energy_balance]="build/tests/capsule/table_energy_balance"
