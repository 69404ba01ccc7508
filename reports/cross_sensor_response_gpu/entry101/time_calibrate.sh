#!/bin/bash
# Research log entry 101, rule 5: `anytip calibrate` at 120 s by response transfer with `cover_informative`, one
# core (taskset -c 0), alternated $1 rounds (default 3) between this entry's run (the plan's residual correction,
# length 1, ratio 10) and its control of the same fold: other16 fold 0 draw 0 on SIM23-000 (control entry 97),
# fleet88 fold 0 on SIM40-000 (control entry 99). Prints each calibration's `wall_s` (fit and fold).
rounds=${1:-3}
G=reports/cross_sensor_response_gpu
pairs="other16_severe_d0/other16_seed0:data/other16:SIM23-000:entry97 fleet88_cpu/fleet88_seed0:data/fleet88:SIM40-000:entry99"
for r in $(seq $rounds); do
  for pair in $pairs; do
    IFS=: read -r arm registry unit control <<< "$pair"
    for entry in $control entry101; do
      run=$G/$entry/$arm
      out=build/time_calibrate101/${entry}_$(dirname $arm)_$r
      rm -rf $out; mkdir -p $(dirname $out)
      OMP_NUM_THREADS=1 taskset -c 0 anytip calibrate --model $run --unit $unit --registry $registry \
        --budget-seconds 120 --method response --plan-strategy cover_informative --out $out > $out.log 2>&1 \
        || { cat $out.log; exit 1; }
      python -c "import json; c=json.load(open('$out/calibration.json')); print('$entry $arm $unit round $r', 'wall_s %.2f' % c['wall_s'], 'robot-s %.1f' % c['calib_seconds'])"
    done
  done
done
