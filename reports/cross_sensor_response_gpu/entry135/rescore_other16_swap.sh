#!/bin/bash
# Research log entry 135: entry 127's swap on today's recipe (the correction centred with ordinary use): entry
# 121's other16 rescoring of fold $1 in start draw $2 on data/other16p, every job with ordinary use given the
# joint codes of its unit's other plan (designed <-> cover_informative), into
# entry135/other16_severe_d$2/other16_seed$1. Run from the root of a worktree of the entry's commit with
# entry127/variant.patch applied.
exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry135
