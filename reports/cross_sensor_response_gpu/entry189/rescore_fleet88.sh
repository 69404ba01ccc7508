#!/bin/bash
# Research log entry 189: entry 122's fleet88 rescoring of fold $1 (as entry 131 ran it: today's recipe with the
# centred correction, both plans, ordinary use) with `options.response.label_free.use_weight: $2`, into
# entry189/w$2/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry189/rescore_fleet88.sh K W
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
exec bash reports/cross_sensor_response_gpu/entry122/rescore_fleet88_designed_use.sh "$1" "entry189/w$2" \
  --set "options.response.label_free={with_plans: true, zero_shot: false, use_weight: $2}"
