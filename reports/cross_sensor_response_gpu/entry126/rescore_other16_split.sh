#!/bin/bash
# Research log entry 126: entry 121's other16 rescoring of fold $1 in start draw $2 on data/other16s (each
# unit's designed run at -90 deg pressed 600 s after power-up, the variant's simulator), into
# entry126/other16_severe_d$2/other16_seed$1. Run from the root of a worktree of the entry's commit with
# variant.patch applied (the power-up tare is the variant's reader).
REGISTRY=data/other16s exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry126
