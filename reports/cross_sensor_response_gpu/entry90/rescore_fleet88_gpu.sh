#!/bin/bash
# Research log entry 91, fleet88's 1,024-unit models: fleet88 fold $1 as entry 86's fleet88_registry (the GPU
# response models of 1,040 units, the registry code prior, 120 s with ordinary use, 24 factor units), its
# plans cover_informative (criterion v), into entry90/fleet88_gpu_cover_informative_v/fleet88_seed$1.
# Control: entry86/fleet88_registry/fleet88_seed$1.
k=$1
reports/cross_sensor_response_gpu/entry86/rescore_fleet88.sh registry $k \
  reports/cross_sensor_response_gpu/entry90/fleet88_gpu_cover_informative_v/fleet88_seed$k \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v
