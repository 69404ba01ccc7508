#!/bin/bash
# Research log entry 86, rule 4: fleet88 fold $2 (default 0) rescored as entry 81's 10-step arm
# (fleet88_it10: the 1,024-unit model, ordinary use, 24 factor units, batches of 512 at lr 0.02,
# 40 epochs, draw 0 of the start network), a new unit's codes fitted under the code prior $1, into
# entry86/fleet88_$1/fleet88_seed$2, or into $3 with rescore_response.py's options $4... added
# (entry 91's plans).
prior=$1; k=${2:-0}; out=${3:-reports/cross_sensor_response_gpu/entry86/fleet88_$prior/fleet88_seed$k}
shift $(( $# < 3 ? $# : 3 ))
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k --registry data/fleet88 \
  --response-model 'reports/cross_sensor_response_gpu/models/fleet88_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false, plan_iterations: 10}" \
  --set options.response.transfer_from=registry \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 --set options.extra_units=null \
  --set options.response.code_prior=$prior "$@" \
  --out "$out"
