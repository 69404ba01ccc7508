#!/bin/bash
# Research log entry 101: entry 97's other16 rescoring of fold $1 in start draw $2 (severe models, `cover` and
# `cover_informative`, criterion v, 10 code steps: the recipe's) with each transferred row corrected by the
# unit's plan residuals (kernel length $3, noise-to-signal $4), into entry101/other16_severe_d$2/other16_seed$1.
# Control: entry97/other16_severe_d$2. The registry is simulated again, so the run's recorded hash is taken as
# that of its runs in it (same_rows.py).
k=$1; d=$2; length=$3; ratio=$4
. reports/cross_sensor_response_gpu/entry83/other16.sh
RESCORE_SCRIPT=reports/cross_sensor_response_gpu/entry101/same_rows.py other16_rescore $k "$TWICE_THE_SPREAD" 60 reports/cross_sensor_response_gpu/entry101/other16_severe_d$d/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.residual_length=$length --set options.response.residual_ratio=$ratio
