#!/bin/bash
# Research log entry 88: one other16 fold ($1) rescored as entry 83's e60_d0 (entry 81's 10-step arm:
# the default-spread 1,024-unit models, batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s,
# ordinary use, the diagonal code prior), the plan's rows weighing $2 times their effective count in
# the fit of its codes, into entry88/w$2/other16_seed$1.
k=$1; w=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry88/w$w/other16_seed$k \
  reports/cross_sensor_response_gpu/entry88/code_weight.py $w
