#!/bin/bash
# Research log entry 208: `bash reports/cross_sensor_designs/run.sh DESIGN SEED [CORE] [--set ...]` runs fold
# SEED of experiments/cross_sensor_designs.yaml on data/DESIGN24 with data/DESIGN_extra128 (DESIGN: edge or
# pad), pinned to CORE (default 0), into reports/cross_sensor_designs/DESIGN_seedSEED; any further arguments go
# to `anytip run` (the pad's folds: --set options.response.steps=5000, the entry's CPU budget).
# REGISTRY and OUT, where set, replace the registry and the run directory (entry 210: data/edge24p, the edge
# units with their designed plans, into edge_designed_seedSEED).
set -euo pipefail
design=$1 seed=$2 core=${3:-0}
shift 3 || shift $#
registry=${REGISTRY:-data/${design}24}
out=${OUT:-reports/cross_sensor_designs/${design}_seed${seed}}
OMP_NUM_THREADS=1 taskset -c "$core" anytip run experiments/cross_sensor_designs.yaml --registry "$registry" \
  --set "options.extra_units.registry=data/${design}_extra128" --set "seeds=[$seed]" --out "$out" "$@"
