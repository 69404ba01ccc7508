#!/bin/bash
# Research log entry 159: the per-unit references of entry 158's fresh held-out units under other16's fold K,
# into entry159/other16f_seedK/references.json: entry 158's script with its driver, response model and output
# changed (sed), so the folds, units and options are entry 158's.
#   bash reports/cross_sensor_response_gpu/entry159/run_other16f.sh K
set -euo pipefail
sed -e 's#entry158/fresh_severe.py#entry159/fresh_references.py#' \
    -e '/_severe.safetensors/d' \
    -e 's#entry158/other16f_seed#entry159/other16f_seed#' \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$@"
