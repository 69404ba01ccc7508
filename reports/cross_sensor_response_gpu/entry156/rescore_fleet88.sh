#!/bin/bash
# Research log entry 156: today's recipe on fleet88 (entry 155's `all` arm: entry 101's driver, the CPU response
# models, the registry code prior, the converged code fit, criterion v, the plan's residual correction) at 30 and
# 120 s, the plan alone, with `cover_informative`'s exchanges kept to one force level (entry 92's cells), fold K,
# on data/fleet88, into entry156/fleet88_seedK. The driver's wrapper is swapped for same_rows_force_cells.py.
#   bash reports/cross_sensor_response_gpu/entry156/rescore_fleet88.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1
sed "s#reports/cross_sensor_response_gpu/entry101/same_rows.py#reports/cross_sensor_response_gpu/entry156/same_rows_force_cells.py#" \
  reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh \
  | bash -s -- "$k" 1 10 entry156 --set "options.budgets=[30, 120]" --set "options.plan_strategies=[cover_informative]"
