#!/bin/bash
# Research log entry 189: entry 121's other16 rescoring of fold $1 in start draw 0 (as entry 130 ran it: today's
# recipe with the centred correction, both plans, ordinary use) with `options.response.label_free.use_weight: $2`,
# into entry189/w$2/other16_severe_d0/other16_seed$1.
#   bash reports/cross_sensor_response_gpu/entry189/rescore_other16.sh K W
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" 0 "entry189/w$2" \
  --set "options.response.label_free={with_plans: true, zero_shot: false, use_weight: $2}"
