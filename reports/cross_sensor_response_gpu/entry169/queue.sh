#!/bin/bash
# Research log entry 169: both folds at once (one core each), logs under entry169/logs/.
#   bash reports/cross_sensor_response_gpu/entry169/queue.sh
G=reports/cross_sensor_response_gpu/entry169
mkdir -p $G/logs
for k in 0 1; do
  /usr/bin/time -v bash $G/rescore_fleet88.sh $k > $G/logs/fleet88_k$k.log 2>&1 &
done
wait
