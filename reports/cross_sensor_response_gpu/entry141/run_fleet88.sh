#!/bin/bash
# Research log entry 141: fleet88 fold $1 (entry 26's run, its response model, the labels alone) scoring the designed
# 600 s plan of registry $2 on its own 4 validation units and the 64 units SIM42-* (entry 100's draw), nothing held
# out, into entry141/$2_seed$1/val_loss_units.json (entry 98's driver). $2: fleet88w6 (the design in place) or
# fleet88w6f (entry 139's variant: the full protocol's press and patch). A later entry may give another budget in
# seconds as $3 (the registry holding each unit's plan<$3>) and another directory under cross_sensor_response_gpu/
# as $4 (entry 145).
set -euo pipefail
k=$1 reg=$2 b=${3:-600} out=${4:-entry141}
export OMP_NUM_THREADS=1 PYTHONPATH=research
python reports/cross_sensor_response_gpu/entry98/more_val.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry "data/$reg" --prefix SIM42- --out "reports/cross_sensor_response_gpu/$out/${reg}_seed$k" \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "data.protocol=[full, short, quick, plan$b]" --set "options.budgets=[$b]" \
  --set "options.plan_strategies=[designed]" --set "options.intervals=null"
