#!/bin/bash
# Research log entry 116: `anytip calibrate` at 120 s by response transfer, the recipe (`cover_informative`, the
# plan's residual correction, the registry code prior, the converged code fit), one core (taskset -c 1, the
# other core idle), on fleet88 fold 0's response model: the plan alone (entry 101's run) and with 600 s of
# ordinary use (entry 106's run), alternated $1 rounds (default 3) over the units named after it (default
# SIM40-000, the unit of every earlier timing, and two of the fold's held-out units). Prints each
# calibration's `wall_s` (fit and fold) and the whole command's seconds.
rounds=${1:-3}; shift; units=${*:-SIM40-000 SIM40-001 SIM40-002}
G=reports/cross_sensor_response_gpu
for r in $(seq $rounds); do
  for unit in $units; do
    for arm in alone use; do
      if [ $arm = alone ]; then run=$G/entry101/fleet88_cpu/fleet88_seed0; extra=""
      else run=$G/entry106/fleet88_cpu_use/fleet88_seed0; extra="--ordinary-use 600"; fi
      out=build/time_calibrate116/${arm}_${unit}_$r
      rm -rf $out; mkdir -p $(dirname $out)
      start=$(date +%s.%N)
      OMP_NUM_THREADS=1 taskset -c 1 anytip calibrate --model $run --unit $unit --registry data/fleet88 \
        --budget-seconds 120 --method response --plan-strategy cover_informative $extra --out $out > $out.log 2>&1 \
        || { cat $out.log; exit 1; }
      end=$(date +%s.%N)
      python -c "import json; c=json.load(open('$out/calibration.json')); print('$arm $unit round $r', 'wall_s %.2f' % c['wall_s'], 'command_s %.1f' % ($end - $start))"
    done
  done
done
