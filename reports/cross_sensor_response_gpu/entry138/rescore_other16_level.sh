#!/bin/bash
# Research log entry 138: entry 121's other16 rescoring (today's recipe) of fold $1 in start draw $2 on
# data/other16p, every joint fit with ordinary use with each barometer's level of the plan's rows left free
# (profiled out), into entry138/other16_severe_d$2/other16_seed$1. Run from the root of a worktree of the entry's
# commit with variant.patch applied.
exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry138
