#!/bin/bash
# Research log entry 145: data/fleet88w3 (fleet88 plus each unit's plan300 and the 64 units SIM42-* with
# full,short,quick,plan300, the design in place: LONG_PLAN_S = 600) and data/fleet88w3f (the same with
# LONG_PLAN_S = 300: the full protocol's press and patch at 300 s), each simulated from a worktree of HEAD with
# that one line set.
#   bash reports/cross_sensor_response_gpu/entry145/make_registries.sh
# Another budget B and registry name R (entry 145's amendments: 450 fleet88w45, 525 fleet88w52):
#   bash reports/cross_sensor_response_gpu/entry145/make_registries.sh B R
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
b=${1:-300} reg=data/${2:-fleet88w3}
root=$PWD
simulate() {  # $1: the registry; $2: LONG_PLAN_S in the tree it is simulated from
  local tree
  tree=$(mktemp -d)/e145
  git worktree add -q --detach "$tree" HEAD
  sed -i "s/^LONG_PLAN_S = .*$/LONG_PLAN_S = $2/" "$tree/research/anytip/sensor/protocols.py"
  grep -q "^LONG_PLAN_S = $2$" "$tree/research/anytip/sensor/protocols.py"
  rm -rf "$1"; cp -a data/fleet88 "$1"
  for args in "--units 88 --seed 40" "--units 64 --seed 42"; do
    (cd "$tree" && PYTHONPATH=research python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" \
      data simulate --registry "$root/$1" $args --protocols "full,short,quick,plan$b")
  done
  git worktree remove --force "$tree"
}
simulate "$reg" 600.0
simulate "${reg}f" "$b.0"
