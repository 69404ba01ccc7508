#!/bin/bash
# Research log entry 83: one other16 fold ($1) rescored as entry 81's 10-step arm did (the
# default-spread 1,024-unit models, batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s, ordinary
# use; today's recipe), with start network draw $2 trained $3 epochs, into entry83/e$3_d$2/other16_seed$1.
k=$1; d=$2; e=$3
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry83/e${e}_d$d/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py $d $e
