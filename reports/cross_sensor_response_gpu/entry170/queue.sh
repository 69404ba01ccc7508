#!/bin/bash
# Entry 170's eight (fold, slice) jobs, two at a time, through entry 163's queue (its wait is for a pattern that
# matches entry 169's queue and not this command line); logs in entry170/logs.
#   bash reports/cross_sensor_response_gpu/entry170/queue.sh
exec bash reports/cross_sensor_response_gpu/entry163/queue.sh reports/cross_sensor_response_gpu/entry170 \
  "entry16[9]/queue[.]sh" "" "0:0 0:32" "1:0 1:32" "2:0 2:32" "3:0 3:32"
