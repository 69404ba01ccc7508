#!/bin/bash
# Research log entry 109: fleet88 fold $1 with its CPU response model and the recipe's settings (entry 101's: the
# registry code prior, the converged code fit, `cover_informative`, the plan's residual correction of length 1 and
# ratio 10), its validation units its own 4 and the 64 units SIM42-* of data/fleet88w, nothing held out (entry 98's
# driver), into entry109/$2/fleet88_seed$1/val_loss_units.json. $2 names the arm: `float64` runs from this
# checkout, `float32` from one with entry 103's float32_kernel.patch applied (the correction's kernel over the
# query rows in float32); the script runs from the checkout whose code it scores, writing into this one's reports.
[ $# -eq 3 ] || { echo "usage: $0 FOLD ARM REPORTS_ROOT" >&2; exit 2; }
k=$1; arm=$2; root=$3
python reports/cross_sensor_response_gpu/entry98/more_val.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88w --prefix SIM42- --out $root/reports/cross_sensor_response_gpu/entry109/$arm/fleet88_seed$k \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10
