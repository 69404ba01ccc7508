#!/bin/bash
# Research log entry 206: entry 204's timing a third time (old = dd5ae1c1, the numpy step; new = this tree), $1 rounds
# (default 3), one core with the other idle.
#   bash reports/cross_sensor_response_gpu/entry206/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry206/logs/time_calibrate.log
ENTRY=206 OLD=dd5ae1c1 exec bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh "$@"
