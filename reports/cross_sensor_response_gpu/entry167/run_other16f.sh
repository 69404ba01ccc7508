#!/bin/bash
# Research log entry 167: entry 164's fold K (its 32 fresh units, the learning rate 0.01) from starts 3 and 4, into
# entry167/other16f_seedK/references.json: entry 164's command with its driver and output changed (sed).
#   bash reports/cross_sensor_response_gpu/entry167/run_other16f.sh K
set -euo pipefail
sed -e 's#entry164/starts.py#entry167/starts.py#' -e 's#entry164/other16f_seed#entry167/other16f_seed#' \
    reports/cross_sensor_response_gpu/entry164/run_other16f.sh | bash -s -- "$@"
