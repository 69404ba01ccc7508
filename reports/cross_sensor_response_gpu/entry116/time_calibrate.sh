#!/bin/bash
# Research log entry 116: `anytip calibrate` at 120 s by response transfer, the recipe (`cover_informative`, the
# plan's residual correction, the registry code prior, the converged code fit), one core (taskset -c 1, the
# other core idle), on fleet88 fold 0's response model: the plan alone (entry 101's run) and with 600 s of
# ordinary use (entry 106's run), alternated $1 rounds (default 3) over the units named after it (default
# SIM40-000, the unit of every earlier timing, and two of the fold's held-out units). Prints each
# calibration's `wall_s` (fit and fold) and the whole command's seconds (and `core_gflops`, entry 171). TIMING_DIR
# (default time_calibrate116) names its directory under build/.
rounds=${1:-3}; shift; units=${*:-SIM40-000 SIM40-001 SIM40-002}
G=reports/cross_sensor_response_gpu
TIMING_DIR=${TIMING_DIR:-time_calibrate116}; . $G/entry116/time_one.sh
for r in $(seq $rounds); do
  for unit in $units; do
    time_one alone $unit $r $G/entry101/fleet88_cpu/fleet88_seed0
    time_one use $unit $r $G/entry106/fleet88_cpu_use/fleet88_seed0 --ordinary-use 600
  done
done
