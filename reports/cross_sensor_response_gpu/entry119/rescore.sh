#!/bin/bash
# Research log entry 119: entry 118's rescoring of a severity run (NAME: severity0.5 | fleet24_seed1 | severity2)
# at 120 s, each plan-calibrated job's codes fitted on its unit's whole calibration (entry 87's oracle, 16,384
# rows) instead of its plan: a ceiling, never a method. Into entry119/NAME. Only `response@cover_informative` is
# read (the `response+use` jobs start their joint fit from the oracle codes).
[ $# -eq 1 ] || { echo "usage: $0 severity0.5|fleet24_seed1|severity2" >&2; exit 2; }
case $1 in
  severity0.5) run=reports/cross_sensor_response_severity/severity0.5; registry=data/sev05 ;;
  severity2) run=reports/cross_sensor_response_severity/severity2; registry=data/sev2 ;;
  fleet24_seed1) run=reports/cross_sensor_response_start/fleet24_seed1; registry=data/fleet24 ;;
  *) echo "unknown run $1" >&2; exit 2 ;;
esac
. reports/cross_sensor_response_gpu/entry118/recipe.sh
python reports/cross_sensor_response_gpu/entry87/oracle_codes.py 16384 --same-rows "$run" --registry $registry \
  --out reports/cross_sensor_response_gpu/entry119/$1 \
  "${RECIPE[@]}" --set "options.budgets=[120]" \
  --set "options.intervals=null"
