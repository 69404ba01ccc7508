#!/bin/bash
# Research log entry 146: today's recipe on other16 (entry 121's rescoring, fold $2, start draw $3) with the
# designed plan of budget B read from the design of B x 1.25 (`options.designed_scale`), on data/other16g.
#   bash reports/cross_sensor_response_gpu/entry146/rescore_other16.sh 600 K D   # against entries 142 / 144
#   bash reports/cross_sensor_response_gpu/entry146/rescore_other16.sh 120 K D   # against entry 130
# Without session conditions (data/other16sg), 120 and 600 s in one run, paired only with each other:
#   bash reports/cross_sensor_response_gpu/entry146/rescore_other16.sh s K 0     # designed_scale 1.25
#   bash reports/cross_sensor_response_gpu/entry146/rescore_other16.sh s1 K 0    # designed_scale 1 (in place)
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
arm=$1 k=$2 d=$3
run=reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh
all=(--added-protocol plan600 --added-protocol plan150 --added-protocol plan750
     --set "data.protocol=[full, short, quick, plan120, plan600, plan150, plan750]")
case $arm in
  600) REGISTRY=data/other16g bash $run "$k" "$d" entry146/at600 --added-protocol plan600 --added-protocol plan750 \
         --set "data.protocol=[full, short, quick, plan120, plan600, plan750]" --set "options.budgets=[600]" \
         --set options.designed_scale=1.25 ;;
  120) REGISTRY=data/other16g bash $run "$k" "$d" entry146/at120 --added-protocol plan150 \
         --set "data.protocol=[full, short, quick, plan120, plan150]" --set options.designed_scale=1.25 ;;
  s) REGISTRY=data/other16sg bash $run "$k" "$d" entry146/nosessions --paired-only "${all[@]}" \
       --set "options.budgets=[120, 600]" --set options.designed_scale=1.25 ;;
  s1) REGISTRY=data/other16sg bash $run "$k" "$d" entry146/nosessions_in_place --paired-only "${all[@]}" \
        --set "options.budgets=[120, 600]" --set options.designed_scale=1 ;;
  *) echo "usage: $0 600|120|s|s1 FOLD DRAW" >&2; exit 2 ;;
esac
