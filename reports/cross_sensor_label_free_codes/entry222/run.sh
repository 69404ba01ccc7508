#!/bin/bash
# Research log entry 222: entry 44's zero-shot arm (the scale-held search from the encoder's codes, 600 s of
# ordinary use spread over the dome) on fold K of REG (other16, the default, or fleet88), its search reading the
# training units' contacts in draw D (`scripts/label_free_codes.py --search-draw D`; draw 0 is entry 44's own
# order). Validation and held-out units alike. From the repository root, with the registries simulated again
# (`anytip data simulate --registry data/other16 --fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23
# --protocols full,short,quick`; `anytip data simulate --registry data/fleet88 --units 88 --seed 40 --protocols
# full,short,quick`; `anytip data simulate --registry data/extra128 --units 128 --seed 8 --protocols full`):
#   bash reports/cross_sensor_label_free_codes/entry222/run.sh D K [REG]
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=${PYTHONPATH:-research}
d=$1 k=$2 reg=${3:-other16}
here=reports/cross_sensor_label_free_codes/entry222
mkdir -p "$here/draw$d" "$here/logs"
python scripts/label_free_codes.py "reports/cross_sensor_response_start/${reg}_seed$k" --registry "data/$reg" \
  --unlabeled spread --pull 0.001 --arms joint_scale_encoder,encoder --search-draw "$d" \
  --out "$here/draw$d/${reg}_seed$k.json" > "$here/logs/draw${d}_${reg}_seed$k.log" 2>&1
