#!/bin/bash
# Research log entry 160: entry 158's fresh held-out units under other16's fold K with 600 s of ordinary use, at
# 120 s, `cover_informative`, into entry160/other16f_seedK/rows.json: entry 158's script with its budgets, plans,
# ordinary use (entry 153's `label_free`) and output changed (sed), so the folds, units and other options are
# entry 158's.
#   bash reports/cross_sensor_response_gpu/entry160/run_other16f.sh K
set -euo pipefail
sed -e 's#"options.budgets=\[30, 120\]"#"options.budgets=[120]" --set "options.response.label_free={with_plans: true, zero_shot: false}"#' \
    -e 's#"options.plan_strategies=\[cover, cover_informative\]"#"options.plan_strategies=[cover_informative]"#' \
    -e 's#entry158/other16f_seed#entry160/other16f_seed#' \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$@"
