#!/bin/bash
# Research log entry 154: data/<REG>d, the registry simulated afresh with its own protocols first (every run of
# data/<REG>p keeps its index and draws) and each unit's designed calibrations of 37.5 and 75 s (plan37.5,
# plan75: the designs of 30 and 60 s over 1 - 0.2, the test patches' share, as entry 146 filled 120 s from 150).
#   bash reports/cross_sensor_response_gpu/entry154/make_registry.sh other16   # 16 units, seed 23
#   bash reports/cross_sensor_response_gpu/entry154/make_registry.sh fleet88   # 88 units, seed 40
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
case $1 in
  other16) args=(--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23) ;;
  fleet88) args=(--units 88 --seed 40) ;;
  *) echo "usage: $0 other16|fleet88" >&2; exit 2 ;;
esac
reg=data/${1}d
rm -rf "$reg.tmp"
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "$reg.tmp" "${args[@]}" --protocols full,short,quick,plan120,plan37.5,plan75
rm -rf "$reg"; mv "$reg.tmp" "$reg"
