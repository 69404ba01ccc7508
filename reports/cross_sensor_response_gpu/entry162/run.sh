#!/bin/bash
# Research log entry 162: fresh units SIM25-(FROM) to SIM25-(FROM+31) of data/other16f under other16's fold K, at
# 120 s, `cover_informative`, the plan alone (rows), or their per-unit references under that fold (references),
# into entry162/other16f_seedK_fromFROM/: entry 158's script (rows) or entry 159's changes of it (references),
# with the slice of units, the budget, the plan and the output changed (sed), so every other option is theirs.
#   bash reports/cross_sensor_response_gpu/entry162/run.sh rows|references K FROM
set -euo pipefail
what=$1 k=$2 from=$3
case $what in
  rows) driver=(-e 's#"options.budgets=\[30, 120\]"#"options.budgets=[120]"#'
                -e 's#"options.plan_strategies=\[cover, cover_informative\]"#"options.plan_strategies=[cover_informative]"#') ;;
  references) driver=(-e 's#entry158/fresh_severe.py#entry159/fresh_references.py#' -e '/_severe.safetensors/d') ;;
  *) echo "usage: $0 rows|references K FROM" >&2; exit 2 ;;
esac
case $from in 0|32|64|96) ;; *) echo "FROM: 0, 32, 64 or 96" >&2; exit 2 ;; esac
sed "${driver[@]}" \
    -e "s#\$((32 \* k)):\$((32 \* k + 32))#$from:$((from + 32))#" \
    -e "s#entry158/other16f_seed\$k#entry162/other16f_seed\${k}_from$from#" \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$k"
