#!/bin/bash
# Research log entry 129: entry 121's other16 rescoring of fold $1 in start draw $2 on data/other16p with 40 steps
# of the joint fit with ordinary use (label_free.plan_iterations) instead of 10, into
# entry129/other16_severe_d$2/other16_seed$1.
exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry129 \
  --set "options.response.label_free={with_plans: true, zero_shot: false, plan_iterations: 40}"
