#!/bin/bash
# Research log entry 86: one other16 fold ($1) rescored as entry 83's e60_d0 (entry 81's 10-step arm:
# the default-spread 1,024-unit models, batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s,
# ordinary use), a new unit's codes fitted under the code prior $2, into entry86/$2/other16_seed$1.
k=$1; prior=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry86/$prior/other16_seed$k \
  scripts/rescore_response.py --set options.response.code_prior=$prior
