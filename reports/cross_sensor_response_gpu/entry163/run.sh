#!/bin/bash
# Research log entry 163: fresh units SIM25-(FROM) to SIM25-(FROM+31) of data/other16f under other16's fold K, at
# 120 s, `cover_informative`, with 600 s of ordinary use (and the plan alone beside), into
# entry163/other16f_seedK_fromFROM/rows.json: entry 158's script with entry 160's changes (budget, ordinary use,
# plan) and entry 162's (the slice of units), so every other option is theirs.
#   bash reports/cross_sensor_response_gpu/entry163/run.sh K FROM
set -euo pipefail
k=$1 from=$2
case $from in 0|32|64|96) ;; *) echo "FROM: 0, 32, 64 or 96" >&2; exit 2 ;; esac
sed -e 's#"options.budgets=\[30, 120\]"#"options.budgets=[120]" --set "options.response.label_free={with_plans: true, zero_shot: false}"#' \
    -e 's#"options.plan_strategies=\[cover, cover_informative\]"#"options.plan_strategies=[cover_informative]"#' \
    -e "s#\$((32 \* k)):\$((32 \* k + 32))#$from:$((from + 32))#" \
    -e "s#entry158/other16f_seed\$k#entry163/other16f_seed\${k}_from$from#" \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$k"
