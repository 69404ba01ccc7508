#!/bin/bash
# Research log entry 137: entry 122's fleet88 rescoring of fold $1 (data/fleet88p, the recipe with ordinary use,
# `cover_informative` and `designed`) with the response model trained again on two threads, into
# entry137/$2/fleet88_seed$1. ARM $2: `code32`, a code of 32 numbers per barometer; `draw1`, code 16 and another
# training draw, run from the root of a worktree of the entry's commit with entry137/variant.patch applied.
k=$1; arm=$2
case $arm in
  code32) set -- --set options.response.code_dim=32 ;;
  draw1) export E137_DRAW=1; set -- ;;
  *) echo "ARM: code32 or draw1" >&2; exit 2 ;;
esac
RETRAIN=2 exec bash reports/cross_sensor_response_gpu/entry122/rescore_fleet88_designed_use.sh "$k" \
  "entry137/$arm" "$@"
