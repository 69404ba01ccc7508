#!/bin/bash
# Research log entry 87: one other16 fold ($1) rescored as entry 83's e60_d0 (entry 81's 10-step arm:
# the default-spread 1,024-unit models, batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s,
# ordinary use), each plan's codes fitted on its unit's whole calibration ($2 rows), into
# entry87/oracle/other16_seed$1. Its `response+use` rows start their joint fit from those codes: not read.
k=$1; rows=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry87/oracle/other16_seed$k \
  reports/cross_sensor_response_gpu/entry87/oracle_codes.py $rows
