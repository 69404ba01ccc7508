#!/bin/bash
# Research log entry 139: entry 79's rescoring of entry 26's fold K of REGISTRY (other16 or fleet88) at 600 s,
# the labels alone, with `cover` and the designed plan side by side, on the registry with each unit's designed
# 600 s calibration added (data/other16q, data/fleet88q), into entry139/REGISTRY_seedK.
#   bash reports/cross_sensor_response_gpu/entry139/rescore.sh other16 K
#   bash reports/cross_sensor_response_gpu/entry139/rescore.sh fleet88 K
# other16s: other16 simulated without sessions (entry 62's configuration) with plan600 added (data/other16sq),
# entry 26's other16 folds rescored on it, the rows paired only with each other (the references are other16's).
#   bash reports/cross_sensor_response_gpu/entry139/rescore.sh other16s K
# A third argument names another registry suffix than q (entry 139's variant design: f, data/other16f and
# data/other16sf), into entry139/REG<suffix>_seedK.
set -euo pipefail
reg=$1 k=$2 suf=${3:-q}
export OMP_NUM_THREADS=1 PYTHONPATH=research
run=reports/cross_sensor_response_start/${reg%s}_seed$k
paired=(); [ "$reg" = other16s ] && paired=(--paired-only)
python scripts/rescore_response.py "$run" "${paired[@]}" \
  --registry "data/${reg}${suf}" --out "reports/cross_sensor_response_gpu/entry139/${reg}${suf#q}_seed$k" \
  --response-model "$run/models/response_seed{seed}.safetensors" \
  --added-protocol plan600 --set "data.protocol=[full, short, quick, plan600]" \
  --set "options.budgets=[600]" --set "options.plan_strategies=[cover, designed]" \
  --set "options.intervals=null"
