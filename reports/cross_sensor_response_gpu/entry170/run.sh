#!/bin/bash
# Research log entry 170: entry 163's job (fresh units SIM25-(FROM) to SIM25-(FROM+31) of data/other16f under
# other16's fold K: the severe models, 120 s, `cover_informative`, 600 s of ordinary use with the plan alone beside)
# with the pooled start network drawn again (entry 83's `start_draw.py`, draw 1: the fold's seed plus 1000, 60
# epochs as the recipe trains it), into entry170/other16f_seedK_fromFROM/rows.json. The command is entry 163's as
# its sed makes it from entry 158's, with entry 83's driver in front of entry 158's script.
#   bash reports/cross_sensor_response_gpu/entry170/run.sh K FROM
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 from=$2 G=reports/cross_sensor_response_gpu
case $k in 0|1|2|3) ;; *) echo "K: 0, 1, 2 or 3" >&2; exit 2 ;; esac
case $from in 0|32|64|96) ;; *) echo "FROM: 0, 32, 64 or 96" >&2; exit 2 ;; esac
RESCORE_SCRIPT=$G/entry158/fresh_severe.py python $G/entry83/start_draw.py 1 60 \
  "$G/models/other16_seed{seed}_extra1024_rps32768_severe.safetensors" \
  reports/cross_sensor_response_start/other16_seed$k --registry data/other16f \
  --prefix SIM25- --units $from:$((from + 32)) \
  --set options.extra_units=null \
  --set options.response.rows_per_step=32768 --set "options.budgets=[120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --out $G/entry170/other16f_seed${k}_from$from
