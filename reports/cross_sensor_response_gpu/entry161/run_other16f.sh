#!/bin/bash
# Research log entry 161: entry 159's references of the fresh held-out units under other16's fold K, with the
# learning rates 0.01 and 0.03 tried where entry 159 tried 0.003 and 0.01, into entry161/other16f_seedK: entry
# 159's command (entry 158's script with its driver, response model and output changed by sed) with
# `reference_lrs` set.
#   bash reports/cross_sensor_response_gpu/entry161/run_other16f.sh K
set -euo pipefail
sed -e 's#entry158/fresh_severe.py#entry159/fresh_references.py#' \
    -e '/_severe.safetensors/d' \
    -e 's#entry158/other16f_seed#entry161/other16f_seed#' \
    -e 's#--set options.extra_units=null#--set options.extra_units=null --set "options.reference_lrs=[0.01, 0.03]"#' \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$@"
