#!/bin/bash
# Research log entry 137's timing: `anytip calibrate --ordinary-use 600` at 120 s (`cover_informative`) with fleet88
# fold 0's response model at a code of 32 (entry137/code32) alternated with entry 131's (code 16), one core
# (taskset -c 1, the other core idle), $1 rounds (default 2) over the units named after it (default entry 116's
# three). Prints each calibration's `wall_s` (fit and fold) and the command's seconds.
rounds=${1:-2}; shift; units=${*:-SIM40-000 SIM40-001 SIM40-002}
G=reports/cross_sensor_response_gpu
TIMING_DIR=time_calibrate137; . $G/entry116/time_one.sh
for r in $(seq $rounds); do
  for unit in $units; do
    time_one code16 $unit $r $G/entry131/fleet88_seed0 --ordinary-use 600
    time_one code32 $unit $r $G/entry137/code32/fleet88_seed0 --ordinary-use 600
  done
done
