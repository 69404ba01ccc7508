#!/bin/bash
# Research log entry 155: today's recipe on fleet88 (entry 101's driver: the CPU response models, the registry code
# prior, the converged code fit, criterion v, the plan's residual correction) at 30 and 120 s, the plan alone, with
# one of its steps taken out (ARM), fold K, on data/fleet88, into entry155/ARM/fleet88_seedK:
#   all       nothing taken out; `cover` beside `cover_informative` (the plan's exchange taken out)
#   prior     the code prior `diagonal` (entry 26's) instead of `registry`
#   fit       the code fit of entry 26's recipe: 10 Gauss-Newton steps, no tolerance
#   residual  no residual correction of the transferred rows
#   bash reports/cross_sensor_response_gpu/entry155/rescore_fleet88.sh ARM K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
arm=$1; k=$2
case $arm in
  all) opts=(--set "options.plan_strategies=[cover, cover_informative]") ;;
  prior) opts=(--set options.response.code_prior=diagonal) ;;
  fit) opts=(--set options.response.code_iterations=10 --set options.response.code_tolerance=0) ;;
  residual) opts=(--set options.response.residual_length=0) ;;
  *) echo "ARM is one of all, prior, fit, residual" >&2; exit 2 ;;
esac
[ "$arm" = all ] || opts=(--set "options.plan_strategies=[cover_informative]" "${opts[@]}")
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 "entry155/$arm" \
  --set "options.budgets=[30, 120]" "${opts[@]}"
