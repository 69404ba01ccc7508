#!/bin/bash
# Research log entry 164: entry 159's references of fold K's fresh units (SIM25-(32K) to SIM25-(32K+31)) from
# three starts at the learning rate 0.01, into entry164/other16f_seedK/references.json: entry 159's command with
# its driver, learning rates and output changed (sed), so the fold, units and options are entry 159's.
#   bash reports/cross_sensor_response_gpu/entry164/run_other16f.sh K
set -euo pipefail
sed -e 's#entry158/fresh_severe.py#entry164/starts.py#' -e '/_severe.safetensors/d' \
    -e 's#--set options.extra_units=null#--set options.extra_units=null --set "options.reference_lrs=[0.01]"#' \
    -e 's#entry158/other16f_seed#entry164/other16f_seed#' \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$@"
