#!/bin/bash
# Research log entry 125: entry 123's other16 rescoring of fold $1 in start draw $2 (the plan's residual
# correction off) with at most 128 of the plan's rows in the joint fit with ordinary use (label_free.plan_rows,
# 2048 in entry 123), into entry125/other16_severe_d$2/other16_seed$1.
bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry125 \
  --set options.response.residual_length=0 \
  --set "options.response.label_free={with_plans: true, zero_shot: false, plan_rows: 128}"
