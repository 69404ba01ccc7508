#!/bin/bash
# Research log entry 98: fleet88 fold $1 with its CPU response model and entry 97's settings (120 s alone, the
# registry code prior, `cover` and `cover_informative`, criterion v), its validation units its own 4 and the 64
# units SIM41-* of data/fleet88v, nothing held out, into entry98/fleet88_seed$1/val_loss_units.json.
k=$1
python reports/cross_sensor_response_gpu/entry98/more_val.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88v --prefix SIM41- --out reports/cross_sensor_response_gpu/entry98/fleet88_seed$k \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v
