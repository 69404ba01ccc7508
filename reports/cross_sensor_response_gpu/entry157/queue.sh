#!/bin/bash
# Entry 157's twelve runs (four folds x three start draws), two at a time; logs in entry157/logs.
#   bash reports/cross_sensor_response_gpu/entry157/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry157
mkdir -p $E/logs
for d in 0 1 2; do
  for pair in "0 1" "2 3"; do
    for k in $pair; do
      /usr/bin/time -v bash $E/rescore_other16.sh $k $d > $E/logs/other16_d${d}_k$k.log 2>&1 &
    done
    wait
  done
done
