#!/bin/bash
# Research log entry 152, in entry 151's variant worktree: entry 151's other16 rescoring of fold $1 in start draw
# $2 on data/other16j$1 (fold $1's within-level design), into entry152/at120/other16_severe_d$2/other16_seed$1.
#   bash reports/cross_sensor_response_gpu/entry152/rescore_other16.sh K D
exec bash reports/cross_sensor_response_gpu/entry151/rescore_other16.sh "$1" "$2" j entry152/at120
