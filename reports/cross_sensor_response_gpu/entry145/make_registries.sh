#!/bin/bash
# Research log entry 145: data/fleet88w3 (fleet88 plus each unit's plan300 and the 64 units SIM42-* with
# full,short,quick,plan300, the design in place) and data/fleet88w3f (the same with LONG_PLAN_S = 300: the full
# protocol's press and patch at 300 s, simulated from a worktree of this commit with that one line changed).
#   bash reports/cross_sensor_response_gpu/entry145/make_registries.sh
# Another budget B and registry name R (entry 145's amendment: 450 fleet88w45):
#   bash reports/cross_sensor_response_gpu/entry145/make_registries.sh B R
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
b=${1:-300} reg=data/${2:-fleet88w3}
root=$PWD
simulate() {  # $1: the registry; $2: the source tree to simulate from
  rm -rf "$1"; cp -a data/fleet88 "$1"
  for args in "--units 88 --seed 40" "--units 64 --seed 42"; do
    (cd "$2" && PYTHONPATH=research python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" \
      data simulate --registry "$root/$1" $args --protocols "full,short,quick,plan$b")
  done
}
simulate "$reg" "$root"
tree=$(mktemp -d)/e145
git worktree add --detach "$tree" HEAD
sed -i "s/^LONG_PLAN_S = 600.0$/LONG_PLAN_S = $b.0/" "$tree/research/anytip/sensor/protocols.py"
grep -q "^LONG_PLAN_S = $b.0$" "$tree/research/anytip/sensor/protocols.py"
simulate "${reg}f" "$tree"
git worktree remove --force "$tree"
