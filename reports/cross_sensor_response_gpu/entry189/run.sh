#!/bin/bash
# Research log entry 189, all of it: other16's control (fold 0 at use_weight 1) and four folds at 4, two at a time,
# then fleet88's two folds at 4 at once. About 40 minutes on two cores.
#   bash reports/cross_sensor_response_gpu/entry189/run.sh > reports/cross_sensor_response_gpu/entry189/logs/run.log 2>&1
set -euo pipefail
E=reports/cross_sensor_response_gpu/entry189
{ taskset -c 0 bash $E/rescore_other16.sh 0 1; taskset -c 0 bash $E/rescore_other16.sh 2 4
  taskset -c 0 bash $E/rescore_other16.sh 3 4; } > $E/logs/other16_a.log 2>&1 &
{ taskset -c 1 bash $E/rescore_other16.sh 0 4; taskset -c 1 bash $E/rescore_other16.sh 1 4; } \
  > $E/logs/other16_b.log 2>&1
wait
taskset -c 0 bash $E/rescore_fleet88.sh 0 4 > $E/logs/fleet88_0.log 2>&1 &
taskset -c 1 bash $E/rescore_fleet88.sh 1 4 > $E/logs/fleet88_1.log 2>&1
wait
echo done
