#!/bin/bash
# Research log entry 158: entry 157's other16 command (the severe models in start draw 0, criterion v, the plan's
# residual correction, 30 and 120 s, the plan alone, `cover` beside `cover_informative`) on other16's fold K, its
# training and validation units as the run's, with the fresh units SIM25-* of data/other16f held out (32 per fold:
# fold K holds out SIM25-(32K) to SIM25-(32K+31)), into entry158/other16f_seedK/rows.json.
#   bash reports/cross_sensor_response_gpu/entry158/run_other16f.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1
case $k in 0|1|2|3) ;; *) echo "usage: $0 0|1|2|3" >&2; exit 2 ;; esac
python reports/cross_sensor_response_gpu/entry158/fresh_severe.py \
  'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768_severe.safetensors' \
  reports/cross_sensor_response_start/other16_seed$k --registry data/other16f \
  --prefix SIM25- --units $((32 * k)):$((32 * k + 32)) \
  --set options.extra_units=null \
  --set options.response.rows_per_step=32768 --set "options.budgets=[30, 120]" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --out reports/cross_sensor_response_gpu/entry158/other16f_seed$k
