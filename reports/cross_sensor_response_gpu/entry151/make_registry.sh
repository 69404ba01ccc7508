#!/bin/bash
# Research log entry 151, in the variant's worktree (entry151/variant.patch): data/other16i$1, other16 simulated
# afresh with the protocols of data/other16g up to plan150 in its order (so every run keeps its index and
# draws), each unit's plan150 pressed at the places and force levels of fold $1's informative design
# (entry151/designs/other16_seed$1.json, `choose_design.py` on that fold's response model).
#   bash reports/cross_sensor_response_gpu/entry151/make_registry.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 reg=data/other16i$1
export ANYTIP_DESIGN_PLACES=reports/cross_sensor_response_gpu/entry151/designs/other16_seed$k.json
rm -rf "$reg.tmp"
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "$reg.tmp" --fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23 \
  --protocols full,short,quick,plan120,plan600,plan150
rm -rf "$reg"; mv "$reg.tmp" "$reg"
