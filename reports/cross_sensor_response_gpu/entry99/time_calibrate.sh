#!/bin/bash
# Research log entry 99, rule 4: `anytip calibrate` at 120 s by response transfer, one core (taskset -c 0),
# alternated $1 rounds (default 3) between entry 97's run (10 Gauss-Newton steps) and entry 99's (at most 40,
# tolerance 1e-4) of the same fold: other16 fold 0 (draw 0) on SIM23-000, fleet88 fold 0 on SIM40-000.
# Prints each calibration's `wall_s` (fit and fold) from calibration.json.
rounds=${1:-3}
G=reports/cross_sensor_response_gpu
pairs="other16_severe_d0/other16_seed0:data/other16:SIM23-000 fleet88_cpu/fleet88_seed0:data/fleet88:SIM40-000"
for r in $(seq $rounds); do
  for pair in $pairs; do
    IFS=: read -r arm registry unit <<< "$pair"
    for entry in entry97 entry99; do
      run=$G/$entry/$arm
      out=build/time_calibrate99/${entry}_$(dirname $arm)_$r
      rm -rf $out; mkdir -p $(dirname $out)
      OMP_NUM_THREADS=1 taskset -c 0 anytip calibrate --model $run --unit $unit --registry $registry \
        --budget-seconds 120 --method response --out $out > $out.log 2>&1 || { cat $out.log; exit 1; }
      python -c "import json; c=json.load(open('$out/calibration.json')); print('$entry $arm $unit round $r', 'wall_s %.2f' % c['wall_s'], 'robot-s %.1f' % c['calib_seconds'], [n for n in c['notes'] if n.startswith('plan')])"
    done
  done
done
