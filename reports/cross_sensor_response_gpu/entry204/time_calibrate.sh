#!/bin/bash
# Research log entry 204: entry 203's timing (entry 196's alternated timing) of the compiled step: old = dd5ae1c1
# (the numpy step, entry 203's new code), new = this tree, $1 rounds (default 3), one core with the other idle.
#   bash reports/cross_sensor_response_gpu/entry204/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry204/logs/time_calibrate.log
ENTRY=204 OLD=dd5ae1c1 exec bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh "$@"
