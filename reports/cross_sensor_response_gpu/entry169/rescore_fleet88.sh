#!/bin/bash
# Research log entry 169: entry 153's fleet88 rescoring of fold $1 (today's recipe on the CPU's response models:
# the registry code prior, the converged code fit, criterion v, the plan's residual correction, centred with
# ordinary use; `cover_informative` alone and with 600 s of ordinary use) at 30, 60 and 120 s, with the pooled
# start network drawn again (entry 83's draw 1: the run's seed plus 1000, 40 epochs as the recipe trains it),
# on data/fleet88, into entry169/fleet88_d1/fleet88_seed$1. Draw 0 is entry 153's run.
#   bash reports/cross_sensor_response_gpu/entry169/rescore_fleet88.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 G=reports/cross_sensor_response_gpu
RESCORE_SCRIPT=$G/entry101/same_rows.py \
python $G/entry83/start_draw.py 1 40 reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out $G/entry169/fleet88_d1/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --set "options.plan_strategies=[cover_informative]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set "options.budgets=[30, 60, 120]"
