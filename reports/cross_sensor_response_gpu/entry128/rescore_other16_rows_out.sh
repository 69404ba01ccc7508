#!/bin/bash
# Research log entry 128: entry 121's other16 rescoring of fold $1 in start draw $2 on data/other16p, every job
# with ordinary use trained on its transferred rows alone (its plan's labeled rows left out of its network;
# codes and correction as the recipe's), into entry128/other16_severe_d$2/other16_seed$1. Run from the root of
# a worktree of the entry's commit with variant.patch applied.
exec bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" entry128
