#!/bin/bash
# Research log entry 109: `anytip calibrate` at 120 s by response transfer (`cover_informative`, the plan's residual
# correction: entry 101's fleet88 fold 0 model, SIM40-000), one core (taskset -c 0), alternated $1 rounds between a
# checkout of the float64 kernel ($2, e.g. a worktree of the commit before the float32 one) and this checkout.
# Prints each calibration's `wall_s` (fit and fold).
rounds=${1:-3}; before=$2
[ -d "$before/research/anytip" ] || { echo "usage: $0 ROUNDS CHECKOUT_OF_THE_FLOAT64_KERNEL" >&2; exit 2; }
run=reports/cross_sensor_response_gpu/entry101/fleet88_cpu/fleet88_seed0
for r in $(seq $rounds); do
  for arm in float64 float32; do
    code=$([ $arm = float64 ] && echo "$before" || pwd)
    out=build/time_calibrate109/${arm}_$r
    rm -rf $out; mkdir -p $(dirname $out)
    PYTHONPATH=$code/research OMP_NUM_THREADS=1 taskset -c 0 python -m anytip.cli calibrate --model $run \
      --unit SIM40-000 --registry data/fleet88 --budget-seconds 120 --method response \
      --plan-strategy cover_informative --out $out > $out.log 2>&1 || { cat $out.log; exit 1; }
    python -c "import json; c=json.load(open('$out/calibration.json')); print('$arm round $r', 'wall_s %.2f' % c['wall_s'])"
  done
done
