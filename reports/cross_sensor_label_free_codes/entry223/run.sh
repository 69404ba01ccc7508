#!/bin/bash
# Research log entry 223: entry 44's zero-shot arm (E, `joint_scale_encoder`) beside the same fit with its
# contacts rescaled to the fleet's force scale and the codes refitted (R, `joint_scale_rescaled`), on fold K of
# REG (fleet88 or other16) at search draw D; any further arguments go to the script (`--validation-only`).
# From the repository root, with the registries simulated again as entry 222's run.sh says:
#   bash reports/cross_sensor_label_free_codes/entry223/run.sh D K REG [--validation-only]
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=${PYTHONPATH:-research}
d=$1 k=$2 reg=$3
shift 3
here=reports/cross_sensor_label_free_codes/entry223
tag=$([ "$#" -gt 0 ] && echo val || echo all)
mkdir -p "$here/draw$d" "$here/logs"
python scripts/label_free_codes.py "reports/cross_sensor_response_start/${reg}_seed$k" --registry "data/$reg" \
  --unlabeled spread --pull 0.001 --arms joint_scale_encoder,joint_scale_rescaled,encoder --search-draw "$d" "$@" \
  --out "$here/draw$d/${reg}_seed${k}_$tag.json" > "$here/logs/draw${d}_${reg}_seed${k}_$tag.log" 2>&1
