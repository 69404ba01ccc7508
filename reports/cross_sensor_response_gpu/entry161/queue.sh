#!/bin/bash
# Entry 161's two folds (0 and 1) at once; logs in entry161/logs. Entry 164 runs its folds through it, naming its
# own directory (its run_other16f.sh K runs a fold):
#   bash reports/cross_sensor_response_gpu/entry161/queue.sh [reports/cross_sensor_response_gpu/entry164]
set -uo pipefail
E=${1:-reports/cross_sensor_response_gpu/entry161}
mkdir -p $E/logs
for k in 0 1; do
  /usr/bin/time -v bash $E/run_other16f.sh $k > $E/logs/other16f_k$k.log 2>&1 &
done
wait
