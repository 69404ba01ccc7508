#!/bin/bash
# Research log entry 91: `anytip calibrate` at 120 s by response transfer on other16 fold 0's held-out
# unit SIM23-000, one core (taskset -c 0), alternated $1 rounds (default 2) between entry 83's e60_d0
# (`cover` plans) and entry 91's cover_informative_v (the plan chosen with the response model, its choice
# counted in the fit's time). Prints each calibration's `wall_s` (fit and fold) from calibration.json.
rounds=${1:-2}
runs="reports/cross_sensor_response_gpu/entry83/e60_d0/other16_seed0 reports/cross_sensor_response_gpu/entry90/cover_informative_v/other16_seed0"
for r in $(seq $rounds); do
  for run in $runs; do
    out=build/time_calibrate/$(basename $(dirname $run))_$r
    rm -rf $out
    OMP_NUM_THREADS=1 taskset -c 0 anytip calibrate --model $run --unit SIM23-000 --registry data/other16 \
      --budget-seconds 120 --method response --out $out > $out.log 2>&1 || { cat $out.log; exit 1; }
    python -c "import json,sys; c=json.load(open('$out/calibration.json')); print('$run', 'round $r', 'wall_s %.2f' % c['wall_s'], 'rows', c['calib_samples'], 'robot-s %.1f' % c['calib_seconds'], [n for n in c['notes'] if n.startswith('plan')])"
  done
done
