#!/bin/bash
# Research log entry 166: the per-unit references of fresh units SIM25-(FROM) to SIM25-(FROM+31) of
# data/other16f under other16's fold K from three starts at the learning rate 0.01, into
# entry166/other16f_seedK_fromFROM/references.json: entry 158's command (sed) with entry 164's driver and
# learning rate, and entry 162's slice of units, so every other option is entry 159's.
#   bash reports/cross_sensor_response_gpu/entry166/run.sh K FROM
set -euo pipefail
k=$1 from=$2
case $from in 0|32|64|96) ;; *) echo "FROM: 0, 32, 64 or 96" >&2; exit 2 ;; esac
sed -e 's#entry158/fresh_severe.py#entry164/starts.py#' -e '/_severe.safetensors/d' \
    -e 's#--set options.extra_units=null#--set options.extra_units=null --set "options.reference_lrs=[0.01]"#' \
    -e "s#\$((32 \* k)):\$((32 \* k + 32))#$from:$((from + 32))#" \
    -e "s#entry158/other16f_seed\$k#entry166/other16f_seed\${k}_from$from#" \
    reports/cross_sensor_response_gpu/entry158/run_other16f.sh | bash -s -- "$k"
