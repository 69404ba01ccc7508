#!/bin/bash
# Research log entry 100: `anytip calibrate` at 120 s on fleet88 fold 0's SIM40-000 with entry 99's model (the
# converged code fit), one core (taskset -c 0), alternated $1 rounds (default 3) between `--plan-strategy cover`
# and `--plan-strategy cover_informative` (the plan chosen with the response model, its choice counted in the
# fit's time). Prints each calibration's `wall_s` (fit and fold) from calibration.json.
rounds=${1:-3}
run=reports/cross_sensor_response_gpu/entry99/fleet88_cpu/fleet88_seed0
for r in $(seq $rounds); do
  for strategy in cover cover_informative; do
    out=build/time_calibrate100/${strategy}_$r
    rm -rf $out; mkdir -p $(dirname $out)
    OMP_NUM_THREADS=1 taskset -c 0 anytip calibrate --model $run --unit SIM40-000 --registry data/fleet88 \
      --budget-seconds 120 --method response --plan-strategy $strategy --out $out > $out.log 2>&1 \
      || { cat $out.log; exit 1; }
    python -c "import json; c=json.load(open('$out/calibration.json')); print('$strategy round $r', 'wall_s %.2f' % c['wall_s'], 'robot-s %.1f' % c['calib_seconds'])"
  done
done
