#!/bin/bash
# Research log entry 144: entry 142's rescoring (today's recipe at 600 s on other16, data/other16f, the 600 s design
# entry 141 chose) of fold $1 in start draw $2, into entry144/other16_severe_d$2/other16_seed$1. Draw 0 is entry 142's.
REGISTRY=data/other16f exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry144 \
  --added-protocol plan600 --set "data.protocol=[full, short, quick, plan120, plan600]" --set "options.budgets=[600]"
