#!/bin/bash
# Research log entry 213: fleet88 and other16 with each unit's designed calibrations run at 1 s moves (the full
# protocol's rest before each patch; `anytip data simulate --move-s 1`), as entry 146's data/REGg holds them at
# 2 s: the registry's own protocols first (added again unchanged), then plan120, plan600 and plan150 in entry
# 146's order, so plan150's runs take the run seeds of entry 146's. data/other16g (entry 146's at 2 s) is built
# again from data/other16 as the control's registry.
#   bash reports/cross_sensor_response_gpu/entry213/make_registries.sh other16m   # data/other16m, 16 units
#   bash reports/cross_sensor_response_gpu/entry213/make_registries.sh other16g   # data/other16g (control)
#   bash reports/cross_sensor_response_gpu/entry213/make_registries.sh fleet88m   # data/fleet88m, 88 units
#   bash reports/cross_sensor_response_gpu/entry213/make_registries.sh fleet88r   # entry 215: data/fleet88r, as
#                                                  # fleet88m with the plans' cells and loads drawn at random
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
reg=$1
case $reg in
  other16m) base=other16 args=(--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23 --move-s 1
                               --protocols full,short,quick,plan120,plan600,plan150) ;;
  other16g) base=other16 args=(--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23
                               --protocols full,short,quick,plan120,plan600,plan150,plan750) ;;
  fleet88m) base=fleet88 args=(--units 88 --seed 40 --move-s 1 --protocols full,short,quick,plan120,plan600,plan150) ;;
  fleet88r) base=fleet88 args=(--units 88 --seed 40 --move-s 1 --plan-points random
                               --protocols full,short,quick,plan120,plan600,plan150) ;;
  *) echo "usage: $0 other16m|other16g|fleet88m|fleet88r" >&2; exit 2 ;;
esac
rm -rf "data/${reg}.tmp"
cp -a "data/$base" "data/${reg}.tmp"
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "data/${reg}.tmp" "${args[@]}"
rm -rf "data/${reg}"; mv "data/${reg}.tmp" "data/${reg}"
