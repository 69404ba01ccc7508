#!/bin/bash
# Research log entry 142: entry 140's rescoring (today's recipe at 600 s on other16, start draw 0, fold $1) on
# data/other16f, whose plan600 runs are the 600 s design entry 141 chose, into entry142/other16_severe_d0/other16_seed$1.
REGISTRY=data/other16f exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" 0 entry142 \
  --added-protocol plan600 --set "data.protocol=[full, short, quick, plan120, plan600]" --set "options.budgets=[600]"
