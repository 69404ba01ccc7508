#!/bin/bash
# Research log entry 222: entry 44's zero-shot arm (the scale-held search from the encoder's codes, 600 s of
# ordinary use spread over the dome) on other16's fold K, its search reading the training units' contacts in
# draw D (`scripts/label_free_codes.py --search-draw D`; draw 0 is entry 44's own order). Validation and
# held-out units alike. From the repository root, with data/other16 simulated again
# (`anytip data simulate --registry data/other16 --fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23
# --protocols full,short,quick`):
#   bash reports/cross_sensor_label_free_codes/entry222/run.sh D K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=${PYTHONPATH:-research}
d=$1 k=$2
here=reports/cross_sensor_label_free_codes/entry222
mkdir -p "$here/draw$d" "$here/logs"
python scripts/label_free_codes.py "reports/cross_sensor_response_start/other16_seed$k" --registry data/other16 \
  --unlabeled spread --pull 0.001 --arms joint_scale_encoder,encoder --search-draw "$d" \
  --out "$here/draw$d/other16_seed$k.json" > "$here/logs/draw${d}_seed$k.log" 2>&1
