#!/bin/bash
# Research log entry 196: entry 172's timing of `anytip calibrate` (fleet88 fold 0's CPU response model,
# `cover_informative` at 120 s, the plan alone and with 600 s of ordinary use, units SIM40-000 to -002, one core
# with the other idle), $1 rounds (default 3), each calibration run with the code before the unit network's numpy
# step (eeee16de, a worktree under build/: "old") and with the current tree ("new") in turn, the order alternating
# by round. Prints 'CODE ARM UNIT round R wall_s S command_s C core_gflops G model H' per calibration.
#   bash reports/cross_sensor_response_gpu/entry196/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry196/logs/time_calibrate.log
# (b2, the same again: > .../logs/time_calibrate_b2.log)
ENTRY=196 OLD=eeee16de exec bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh "$@"
