#!/bin/bash
# Research log entry 89: one other16 fold ($1) rescored as entry 83's e60_d0, each plan's codes fitted on
# $2 times its press count of random whole presses of its unit's calibration, into
# entry89/f$2/other16_seed$1. Its `response+use` rows start their joint fit from those codes: not read.
k=$1; f=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry89/f$f/other16_seed$k \
  reports/cross_sensor_response_gpu/entry89/random_presses.py $f
