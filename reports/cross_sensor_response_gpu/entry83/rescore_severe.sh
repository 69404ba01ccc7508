#!/bin/bash
# Research log entry 83, third part: one other16 fold ($1) rescored as entry 80 did (the 1,024 extra
# units drawn at twice the default spread; batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s,
# ordinary use) with today's recipe (10 steps of the joint fit) and start network draw $2 (60 epochs),
# into entry83/severe_d$2/other16_seed$1.
k=$1; d=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$TWICE_THE_SPREAD" 60 reports/cross_sensor_response_gpu/entry83/severe_d$d/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60
