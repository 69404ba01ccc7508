#!/bin/bash
# Research log entry 118: the recipe of today (`cover_informative` plans, the registry code prior, the converged code
# fit, the plan's residual correction, each unit's 600 s of ordinary use beside the plan alone; intervals from the
# plan x the fleet factor of the run's 2 validation units) at 120 and 600 s, by rescoring a severity run of entries
# 26, 32 and 34 (fleet24's seed and split, 6 held-out units) on its own response model and references:
#   rescore.sh severity0.5 | severity2 | severity2_extra2 | fleet24_seed1
# into entry118/<name>. The registries are simulated again from the commands of
# reports/cross_sensor_response_severity/README.md (data/sev05, data/sev2, data/extra128, data/extra128_sev2) and
# reports/cross_sensor_response_start/README.md (data/fleet24); a severity run's saved per-unit references are
# scored again on them (--references), the gate that the rebuilt registry holds the run's rows.
[ $# -eq 1 ] || { echo "usage: $0 severity0.5|severity2|severity2_extra2|fleet24_seed1" >&2; exit 2; }
case $1 in
  severity0.5) run=reports/cross_sensor_response_severity/severity0.5; registry=data/sev05 ;;
  severity2|severity2_extra2) run=reports/cross_sensor_response_severity/$1; registry=data/sev2 ;;
  fleet24_seed1) run=reports/cross_sensor_response_start/fleet24_seed1; registry=data/fleet24 ;;
  *) echo "unknown run $1" >&2; exit 2 ;;
esac
. reports/cross_sensor_response_gpu/entry118/recipe.sh
refs=(); [ -d "$run/models/per_unit_seed1_lr0" ] && refs=(--references "$run/models")
python reports/cross_sensor_response_gpu/entry101/same_rows.py "$run" --registry $registry \
  --out reports/cross_sensor_response_gpu/entry118/$1 "${refs[@]}" \
  "${RECIPE[@]}" --set "options.budgets=[120, 600]" \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false}"
