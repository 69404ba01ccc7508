#!/bin/bash
# Research log entry 140: today's recipe on other16 (entry 121's rescoring of fold $1 in start draw 0: the severe
# models, `cover_informative` by criterion v, the plan's residual correction centred with ordinary use) at 600 s,
# `cover_informative` and the designed plan side by side, on data/other16q (entry 139: other16p plus plan600), into
# entry140/other16_severe_d0/other16_seed$1.
REGISTRY=data/other16q exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" 0 entry140 \
  --added-protocol plan600 --set "data.protocol=[full, short, quick, plan120, plan600]" --set "options.budgets=[600]"
