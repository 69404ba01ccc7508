#!/bin/bash
# Research log entry 173: entry 146's fleet88 rescoring of fold $1 at 120 s (today's recipe on the CPU's response
# models: entry 101's options with the correction's kernel length 1 and noise-to-signal 10; the designed plan read
# from the design of 150 s, `designed_scale: 1.25`; alone and with 600 s of ordinary use) with the pooled start
# network drawn again (entry 83's draw 1: the run's seed plus 1000, 40 epochs), on data/fleet88g, into
# entry173/fleet88_d1/fleet88_seed$1. Draw 0 is entry 146's run (entry146/at120).
#   bash reports/cross_sensor_response_gpu/entry173/rescore_fleet88.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 G=reports/cross_sensor_response_gpu
RESCORE_SCRIPT=$G/entry101/same_rows.py \
python $G/entry83/start_draw.py 1 40 reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88g --out $G/entry173/fleet88_d1/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --added-protocol plan120 --added-protocol plan150 --set "data.protocol=[full, short, quick, plan120, plan150]" \
  --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[120]" \
  --set options.designed_scale=1.25
