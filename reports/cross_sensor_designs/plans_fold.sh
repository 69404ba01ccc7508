#!/bin/bash
# Research log entry 214: `bash reports/cross_sensor_designs/plans_fold.sh ARM SEED CORE` runs entries 211-212's
# command on fold SEED of the edge sensor, ARM rhythm (data/edge24f, the Halton points) or random (data/edge24r),
# into reports/cross_sensor_designs/edge_ARM_seedSEED. The fold's response model is entry 209's
# (edge_seedSEED/models), copied in first: its training digest is this run's (the registries' full and short runs
# are data/edge24's), so the run reuses it as a run resumed in place does, instead of training it again.
set -euo pipefail
arm=$1 seed=$2 core=$3
case $arm in
  rhythm) registry=data/edge24f ;;
  random) registry=data/edge24r ;;
  *) echo "usage: $0 rhythm|random SEED CORE" >&2; exit 2 ;;
esac
here=reports/cross_sensor_designs
out=$here/edge_${arm}_seed${seed}
mkdir -p "$out/models"
cp "$here/edge_seed${seed}/models/response_seed${seed}".{json,safetensors} "$out/models/"
REGISTRY=$registry OUT=$out bash "$here/run.sh" edge "$seed" "$core" \
  --set "options.plan_strategies=[cover_informative,designed]" \
  --set "data.protocol=[full,short,plan30,plan60,plan120,plan600]" --set "options.budgets=[0,30,60,120,600]" \
  --set options.rig.move_s=0.4
