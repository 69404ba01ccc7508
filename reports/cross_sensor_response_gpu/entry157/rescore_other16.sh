#!/bin/bash
# Research log entry 157: entry 153's other16 command (entry 121's options: the severe models, criterion v, the
# plan's residual correction, start draw D) at 30 and 120 s, the plan alone, `cover` beside `cover_informative`,
# fold K, on data/other16, into entry157/other16_severe_dD/other16_seedK: entry 153's script with its budgets,
# ordinary use, strategies and output changed (sed), so the two commands differ in those alone.
#   bash reports/cross_sensor_response_gpu/entry157/rescore_other16.sh K D
set -euo pipefail
sed -e 's#"options.budgets=\[10, 30, 60, 120\]"#"options.budgets=[30, 120]"#' \
    -e '/options.response.label_free=/d' \
    -e 's#"options.plan_strategies=\[cover_informative\]"#"options.plan_strategies=[cover, cover_informative]"#' \
    -e 's#entry153/other16_severe#entry157/other16_severe#' \
    reports/cross_sensor_response_gpu/entry153/rescore_other16.sh | bash -s -- "$@"
