#!/bin/bash
# Research log entry 132: entry 121's other16 rescoring (today's recipe, the correction centred with ordinary
# use) of fold $2 in start draw $3 on data/other16p, every job with ordinary use starting its joint fit where
# arm $1 says (`rounds`: the search's rounds from the plan's own codes; `free`: the label-free search from the
# encoder's codes), into entry132/$1/other16_severe_d$3/other16_seed$2. Run from the root of a worktree of
# the entry's commit with variant.patch applied.
arm=$1; shift
E132_START=$arm exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" \
  "entry132/$arm"
