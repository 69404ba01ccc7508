#!/bin/bash
# Research log entry 213: entry 146's rescoring at 120 s (today's recipe on the CPU's response models, the designed
# plan read from the design of 150 s, `designed_scale: 1.25`, alone and with 600 s of ordinary use) with the
# designed runs at 1 s moves and the rig declaring them (`options.rig.move_s=1`), `cover_informative` priced the
# same beside it, into entry213/m1/.
#   bash reports/cross_sensor_response_gpu/entry213/rescore.sh other16 K   # K = 0..3, start draw 0, data/other16m
#   bash reports/cross_sensor_response_gpu/entry213/rescore.sh fleet88 K   # K = 0, 1, data/fleet88m
#   bash reports/cross_sensor_response_gpu/entry213/rescore.sh fleet88r K  # entry 215: data/fleet88r, into
#                                                                          # entry215/r1
#   bash reports/cross_sensor_response_gpu/entry213/rescore.sh control 0   # entry 146's other16 fold 0 again, on
#                                                                          # data/other16g, into entry213/control
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
arm=$1 k=$2
designed=(--added-protocol plan150 --set "data.protocol=[full, short, quick, plan120, plan150]"
          --set options.designed_scale=1.25)
moves=(--set options.rig.move_s=1)
case $arm in
  other16) REGISTRY=data/other16m bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh \
             "$k" 0 entry213/m1 "${designed[@]}" "${moves[@]}" ;;
  control) REGISTRY=data/other16g bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh \
             "$k" 0 entry213/control "${designed[@]}" ;;
  fleet88|fleet88r) registry=data/fleet88m out=entry213/m1
           [ "$arm" = fleet88r ] && registry=data/fleet88r out=entry215/r1
           REGISTRY=$registry bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 \
             "$out" --added-protocol plan120 "${designed[@]}" "${moves[@]}" \
             --set "options.plan_strategies=[cover_informative, designed]" \
             --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[120]" ;;
  *) echo "usage: $0 other16|fleet88|fleet88r|control FOLD" >&2; exit 2 ;;
esac
