#!/bin/bash
# Entry 160's four folds, two at a time; logs in entry160/logs.
#   bash reports/cross_sensor_response_gpu/entry160/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry160
mkdir -p $E/logs
for pair in "0 1" "2 3"; do
  for k in $pair; do
    /usr/bin/time -v bash $E/run_other16f.sh $k > $E/logs/other16f_k$k.log 2>&1 &
  done
  wait
done
