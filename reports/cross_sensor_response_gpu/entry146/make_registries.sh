#!/bin/bash
# Research log entry 146: data/REGg, data/REGf (the 600 s design in place) plus each unit's designed calibrations
# of 150 and 750 s (plan150, plan750: the designs of 120 and 600 s over 1 - 0.2, the test patches' share),
# simulated with the registry's own protocols first, so every run already there is added again unchanged.
#   bash reports/cross_sensor_response_gpu/entry146/make_registries.sh other16   # 16 units, seed 23
#   bash reports/cross_sensor_response_gpu/entry146/make_registries.sh fleet88   # 88 units, seed 40
#   bash reports/cross_sensor_response_gpu/entry146/make_registries.sh other16s  # other16 without sessions
# other16s: data/other16sg, other16 simulated whole with entry 62's configuration (no per-run session conditions)
# and every protocol above, in that order (data/other16sf's plan600 runs were simulated by an earlier tree).
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
reg=$1
case $reg in
  other16) args=(--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23) ;;
  fleet88) args=(--units 88 --seed 40) ;;
  other16s) args=(--fleet reports/cross_sensor_response_gpu/entry62/other_elastomer_one_session.yaml --units 16
                  --seed 23) ;;
  *) echo "usage: $0 other16|fleet88|other16s" >&2; exit 2 ;;
esac
rm -rf "data/${reg}g.tmp"
[ "$reg" = other16s ] || cp -a "data/${reg}f" "data/${reg}g.tmp"
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "data/${reg}g.tmp" "${args[@]}" --protocols full,short,quick,plan120,plan600,plan150,plan750
rm -rf "data/${reg}g"; mv "data/${reg}g.tmp" "data/${reg}g"
