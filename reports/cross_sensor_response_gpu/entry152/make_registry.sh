#!/bin/bash
# Research log entry 152, in entry 151's variant worktree: data/other16j$1, entry 151's other16 registry with fold
# $1's within-level design (entry152/designs/other16_seed$1.json, `entry151/choose_design.py --same-level`).
#   bash reports/cross_sensor_response_gpu/entry152/make_registry.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 reg=data/other16j$1
export ANYTIP_DESIGN_PLACES=reports/cross_sensor_response_gpu/entry152/designs/other16_seed$k.json
rm -rf "$reg.tmp"
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "$reg.tmp" --fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23 \
  --protocols full,short,quick,plan120,plan600,plan150
rm -rf "$reg"; mv "$reg.tmp" "$reg"
