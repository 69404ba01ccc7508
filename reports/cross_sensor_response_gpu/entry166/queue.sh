#!/bin/bash
# Entry 166's eight (fold, slice) jobs, two at a time, after entry 165's queue, through entry 163's queue: first
# the six of entry 162's (fold, slice) pairs that entry 164 did not run, then folds 2 and 3's own units (entries
# 158-160); logs in entry166/logs.
#   bash reports/cross_sensor_response_gpu/entry166/queue.sh
exec bash reports/cross_sensor_response_gpu/entry163/queue.sh reports/cross_sensor_response_gpu/entry166 \
  entry165/queue.sh "" "0:32 1:0" "2:0 2:32" "3:0 3:32" "2:64 3:96"
