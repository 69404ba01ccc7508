#!/bin/bash
# Research log entry 200: entry 196's alternated timing of `anytip calibrate` (fleet88 fold 0's CPU response
# model, `cover_informative` at 120 s, the plan alone and with 600 s of ordinary use, SIM40-000 to -002, one core
# with the other idle; old: eeee16de, the code before the unit network's numpy step; new: this tree), $1 rounds
# (default 3), run while the cores' probes read 89-90 GFLOP/s.
#   bash reports/cross_sensor_response_gpu/entry200/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry200/logs/time_calibrate.log
ENTRY=200 OLD=eeee16de exec bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh "$@"
