#!/bin/bash
# Research log entry 84, second part: one other16 fold ($1) rescored as entry 83's e60_d0, each unit's
# network one member alone trained $2 epochs from the same start network (draw 0, 60 epochs), into
# entry84/member$2/other16_seed$1.
k=$1; e=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" $e reports/cross_sensor_response_gpu/entry84/member$e/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py 0 60
