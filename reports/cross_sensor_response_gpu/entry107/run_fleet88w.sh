#!/bin/bash
# Research log entry 107: entry 106's fold $1 (the recipe with ordinary use and the plan's residual correction,
# its response model, its 28 learners) with the fresh units SIM42-* of data/fleet88w held out, the first 32
# under fold 0 and the last 32 under fold 1, into entry107/fleet88w_seed$1.
case $1 in 0) units=0:32 ;; 1) units=32:64 ;; *) echo "usage: $0 0|1" >&2; exit 2 ;; esac
python reports/cross_sensor_response_gpu/entry107/fresh_held_out.py \
  reports/cross_sensor_response_gpu/entry106/fleet88_cpu_use/fleet88_seed$1 --registry data/fleet88w \
  --prefix SIM42- --units $units --out reports/cross_sensor_response_gpu/entry107/fleet88w_seed$1
