#!/bin/bash
# Entry 164's folds 0 and 1 at once; logs in entry164/logs.
#   bash reports/cross_sensor_response_gpu/entry164/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry164
mkdir -p $E/logs
for k in 0 1; do
  /usr/bin/time -v bash $E/run.sh $k > $E/logs/other16f_k$k.log 2>&1 &
done
wait
