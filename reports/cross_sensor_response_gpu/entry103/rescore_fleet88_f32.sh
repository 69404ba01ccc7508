#!/bin/bash
# Research log entry 103: entry 101's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# the converged code fit, the plan's residual correction of length 1 and ratio 10: the recipe's), `cover_informative`
# alone, with the code of the checkout it runs from (float32_kernel.patch applied: the correction's kernel over the
# query rows in float32), into entry103/fleet88_cpu/fleet88_seed$1. Control: entry101/fleet88_cpu.
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 entry103/fleet88_cpu \
  --set "options.plan_strategies=[cover_informative]"
