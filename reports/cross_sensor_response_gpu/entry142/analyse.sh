#!/bin/bash
# Research log entry 142's tables (logs/analyse.log):  bash reports/cross_sensor_response_gpu/entry142/analyse.sh
export PYTHONPATH=research
e=reports/cross_sensor_response_gpu/entry142/other16_severe_d0
bash reports/cross_sensor_response_gpu/entry140/analyse.sh $e
echo "== over entry 140 (the design it replaced), per unit"
python scripts/fold_table.py $(echo $e/other16_seed{0,1,2,3}) \
  --against $(echo reports/cross_sensor_response_gpu/entry140/other16_severe_d0/other16_seed{0,1,2,3}) | grep -v '^|'
