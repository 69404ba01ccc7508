#!/bin/bash
# Research log entry 124: entry 122's fleet88 rescoring of fold $1 with the plan's residual correction off
# (residual_length 0), into entry124/fleet88_seed$1.
bash reports/cross_sensor_response_gpu/entry122/rescore_fleet88_designed_use.sh "$1" entry124 \
  --set options.response.residual_length=0
