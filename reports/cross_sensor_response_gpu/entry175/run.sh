#!/bin/bash
# Research log entry 175: the unit network's step, eager against four compiled variants, each in a process of
# its own on one core (taskset -c 1, the other idle), cold (an empty inductor cache directory of its own under
# build/) then warm (the same directory again); and the step's products apart, twice. ~5 minutes.
#   bash reports/cross_sensor_response_gpu/entry175/run.sh > reports/cross_sensor_response_gpu/entry175/logs/step_cost.log
set -euo pipefail
here=reports/cross_sensor_response_gpu/entry175
run() { OMP_NUM_THREADS=1 PYTHONPATH=research taskset -c 1 python $here/step_cost.py "$@" 2>&1 | tail -1; }
run products
for v in default cpp_wrapper max_autotune cpp_wrapper+max_autotune; do
  cache=build/entry175_inductor_${v/+/_}; rm -rf $cache
  for state in cold warm; do
    echo "$state $(TORCHINDUCTOR_CACHE_DIR=$(pwd)/$cache run $v)"
  done
done
run products
