#!/bin/bash
# Research log entry 165: the per-unit references of registry $1's fold $2 (the run
# reports/cross_sensor_response_start/$1_seed$2 on data/$1, whose references every target's rows keep) from three
# starts, into entry165/$1_seed$2/references.json, with its log in entry165/logs/.
#   bash reports/cross_sensor_response_gpu/entry165/run.sh fleet88|other16 K
set -euo pipefail
here=reports/cross_sensor_response_gpu/entry165
mkdir -p "$here/logs"
python "$here/references.py" "reports/cross_sensor_response_start/$1_seed$2" --registry "data/$1" \
  --out "$here/$1_seed$2" --set options.extra_units=null --set options.reference_starts=3 \
  > "$here/logs/$1_seed$2.log" 2>&1
