#!/bin/bash
# Research log entry 120: entry 118's rescoring of entry 34's `severity2_extra2` (severity-2 registry, 128 extra
# units at severity 2) with its response model trained again at a code of 32 numbers per barometer instead of 16
# (--retrain --set options.response.code_dim=32), into entry120/severity2_extra2_code32. Two threads.
. reports/cross_sensor_response_gpu/entry118/recipe.sh
OMP_NUM_THREADS=2 python reports/cross_sensor_response_gpu/entry101/same_rows.py \
  reports/cross_sensor_response_severity/severity2_extra2 --registry data/sev2 \
  --out reports/cross_sensor_response_gpu/entry120/severity2_extra2_code32 --retrain \
  --references reports/cross_sensor_response_severity/severity2_extra2/models \
  --set options.response.code_dim=32 \
  "${RECIPE[@]}" --set "options.budgets=[120, 600]" \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false}"
