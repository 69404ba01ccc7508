#!/bin/bash
# Entry 155's four arms one after another, each arm's two folds at once (two cores); logs in entry155/logs.
#   bash reports/cross_sensor_response_gpu/entry155/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry155
mkdir -p $E/logs
for arm in all prior fit residual; do
  for k in 0 1; do
    /usr/bin/time -v bash $E/rescore_fleet88.sh $arm $k > $E/logs/${arm}_k$k.log 2>&1 &
  done
  wait
done
