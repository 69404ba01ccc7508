#!/bin/bash
# Research log entry 123: entry 121's other16 rescoring of fold $1 in start draw $2 with the plan's residual
# correction off (residual_length 0), into entry123/other16_severe_d$2/other16_seed$1.
bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry123 \
  --set options.response.residual_length=0
