#!/bin/bash
# Research log entry 217: `bash reports/cross_sensor_designs/pad_plans_fold.sh SEED CORE` runs entry 208's spec on
# fold SEED of the pad (data/pad24p: data/pad24's units with their designed plans of 30, 120 and 600 s), with the
# plans `cover`, `cover_informative` and `designed` side by side, into reports/cross_sensor_designs/pad_plans_seedSEED.
# Fold 0's response model is entry 208's (pad_seed0/models), copied in first where the fold is 0: its training
# digest is this run's (data/pad24p's full and short runs are data/pad24's), so the run reuses it.
set -euo pipefail
seed=$1 core=$2
here=reports/cross_sensor_designs
out=$here/pad_plans_seed${seed}
mkdir -p "$out/models"
if [ -f "$here/pad_seed${seed}/models/response_seed${seed}.json" ]; then
  cp "$here/pad_seed${seed}/models/response_seed${seed}".{json,safetensors} "$out/models/"
fi
REGISTRY=data/pad24p OUT=$out bash "$here/run.sh" pad "$seed" "$core" --set options.response.steps=5000 \
  --set "options.plan_strategies=[cover,cover_informative,designed]" \
  --set "data.protocol=[full,short,plan30,plan120,plan600]"
