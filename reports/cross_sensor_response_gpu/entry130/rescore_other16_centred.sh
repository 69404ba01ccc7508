#!/bin/bash
# Research log entry 130: entry 121's other16 rescoring of fold $1 in start draw $2 on data/other16p, every job
# with ordinary use learning its correction from its plan's residuals less each barometer's mean, into
# entry130/other16_severe_d$2/other16_seed$1. Run from the root of a worktree of the entry's commit with
# variant.patch applied.
exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry130
