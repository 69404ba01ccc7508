#!/bin/bash
# Research log entry 101: entry 99's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# 120 s alone, both plans, the converged code fit: the recipe's) with each transferred row corrected by the
# unit's plan residuals (kernel length $2, noise-to-signal $3), into entry101/fleet88_cpu/fleet88_seed$1.
# Control: entry99/fleet88_cpu. The registry is simulated again (same_rows.py). A later entry may give
# another directory under cross_sensor_response_gpu/ as $4 and more `--set` options after it (the last wins),
# and another registry holding fleet88's runs in REGISTRY (default data/fleet88). With RETRAIN=N the response
# model is trained again on N threads instead of read from the run. With DRAW=D (entry 174) the pooled start network
# is entry 83's draw D (the run's seed plus 1000 D, 40 epochs, `entry83/start_draw.py`) instead of the run's.
k=$1; length=$2; ratio=$3; out=${4:-entry101/fleet88_cpu}; shift $(( $# < 4 ? $# : 4 ))
model=(--response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors")
[ -n "$RETRAIN" ] && model=(--retrain --set "threads=$RETRAIN")
script=reports/cross_sensor_response_gpu/entry101/same_rows.py run=(python "$script")
[ -n "$DRAW" ] && run=(env RESCORE_SCRIPT="$script" python reports/cross_sensor_response_gpu/entry83/start_draw.py "$DRAW" 40)
"${run[@]}" reports/cross_sensor_response_start/fleet88_seed$k \
  --registry "${REGISTRY:-data/fleet88}" --out reports/cross_sensor_response_gpu/$out/fleet88_seed$k \
  "${model[@]}" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=$length --set options.response.residual_ratio=$ratio "$@"
