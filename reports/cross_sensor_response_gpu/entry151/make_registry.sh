#!/bin/bash
# Research log entry 151, in the variant's worktree (entry151/variant.patch): data/<REG>i$K, the registry
# simulated afresh with the protocols of data/<REG>g up to plan150 in its order (so every run keeps its index
# and draws), each unit's plan150 pressed at the places and force levels of fold K's informative design
# (entry151/designs/<REG>_seed$K.json, `choose_design.py` on that fold's response model).
#   bash reports/cross_sensor_response_gpu/entry151/make_registry.sh K           # other16, 16 units, seed 23
#   bash reports/cross_sensor_response_gpu/entry151/make_registry.sh fleet88 K   # fleet88, 88 units, seed 40
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
if [ "$1" = fleet88 ]; then
  name=fleet88 k=$2 args=(--units 88 --seed 40)
else
  name=other16 k=$1 args=(--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23)
fi
reg=data/${name}i$k
export ANYTIP_DESIGN_PLACES=reports/cross_sensor_response_gpu/entry151/designs/${name}_seed$k.json
rm -rf "$reg.tmp"
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "$reg.tmp" "${args[@]}" --protocols full,short,quick,plan120,plan600,plan150
rm -rf "$reg"; mv "$reg.tmp" "$reg"
