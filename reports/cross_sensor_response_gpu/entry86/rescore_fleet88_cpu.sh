#!/bin/bash
# Research log entry 86, fourth part: entry 79's fleet88 fold $1 (entry 26's response models of 16
# registry and 128 simulated units, trained on a CPU; the labels alone; each budget's jobs in a fleet of
# their own) at 120 s alone, a new unit's codes fitted under the registry prior, into
# entry86/fleet88_cpu_registry/fleet88_seed$1. Paired with ../../cross_sensor_budgets/fleet88_grouped_seed$1.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry86/fleet88_cpu_registry/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry
