#!/bin/bash
# Research log entry 100: fleet88 fold $1 with its CPU response model, entry 97's settings and entry 99's code fit
# (at most 40 Gauss-Newton steps, tolerance 1e-4), its validation units its own 4 and the 64 units SIM42-* of
# data/fleet88w, nothing held out, into entry100/fleet88_seed$1/val_loss_units.json (entry 98's driver).
k=$1
python reports/cross_sensor_response_gpu/entry98/more_val.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88w --prefix SIM42- --out reports/cross_sensor_response_gpu/entry100/fleet88_seed$k \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4
