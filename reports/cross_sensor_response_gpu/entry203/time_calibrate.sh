#!/bin/bash
# Research log entry 203: entry 200's timing again (entry 196's alternated timing; old: eeee16de, new: this
# tree), $1 rounds (default 3), begun while core 1's probes read 88-90 GFLOP/s.
#   bash reports/cross_sensor_response_gpu/entry203/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry203/logs/time_calibrate.log
ENTRY=203 OLD=eeee16de exec bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh "$@"
