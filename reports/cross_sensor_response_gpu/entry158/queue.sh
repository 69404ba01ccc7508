#!/bin/bash
# Entry 158's four folds, two at a time; logs in entry158/logs. Entries 159 and 160 run theirs through it, naming
# their own directory (its run_other16f.sh K runs a fold):
#   bash reports/cross_sensor_response_gpu/entry158/queue.sh [reports/cross_sensor_response_gpu/entry159]
set -uo pipefail
E=${1:-reports/cross_sensor_response_gpu/entry158}
mkdir -p $E/logs
for pair in "0 1" "2 3"; do
  for k in $pair; do
    /usr/bin/time -v bash $E/run_other16f.sh $k > $E/logs/other16f_k$k.log 2>&1 &
  done
  wait
done
