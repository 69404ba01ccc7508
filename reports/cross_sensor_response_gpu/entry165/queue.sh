#!/bin/bash
# Research log entry 165: every fold of other16 and fleet88, two at a time (one CPU thread each).
#   nohup bash reports/cross_sensor_response_gpu/entry165/queue.sh &
set -uo pipefail
run=reports/cross_sensor_response_gpu/entry165/run.sh
bash $run other16 0 & bash $run other16 1 & wait
bash $run other16 2 & bash $run other16 3 & wait
bash $run fleet88 0 & bash $run fleet88 1 & wait
