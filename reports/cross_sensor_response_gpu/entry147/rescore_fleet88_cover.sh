#!/bin/bash
# Research log entry 147, its second arm: entry 110's rescoring of fold $1 (`cover_informative`, the recipe with the
# plan's residual correction, alone and with 600 s of ordinary use, 24 factor units, every unit tested on both its
# sessions) on data/fleet88h, whose test sessions are another draw than data/fleet88r's (each unit's runs are
# numbered in turn, and there the test session follows its designed runs), so that both plans' intervals are read
# on the same test rows. Into entry147/cover120/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry147/rescore_fleet88_cover.sh K   # K = 0, 1
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 FOLD" >&2; exit 2; }
export OMP_NUM_THREADS=1 PYTHONPATH=research
bash reports/cross_sensor_response_gpu/entry108/rescore_fleet88_retest.sh "$1" entry147/cover120 \
  --registry data/fleet88h --set splits.test_rows=all_sessions
