#!/bin/bash
# Research log entry 98, second part: other16 fold $1 with the severe response models in start draw 0 (entry 83's
# start_draw.py, 60 epochs), entry 97's settings at 120 s alone (`cover` and `cover_informative`, criterion v, no
# ordinary use), its validation units its own 2 and the 64 units SIM24-* of data/other16v, nothing held out, into
# entry98/other16_d0/other16_seed$1/val_loss_units.json.
k=$1
RESCORE_SCRIPT=reports/cross_sensor_response_gpu/entry98/more_val.py \
python reports/cross_sensor_response_gpu/entry83/start_draw.py 0 60 reports/cross_sensor_response_start/other16_seed$k \
  --registry data/other16v --prefix SIM24- --out reports/cross_sensor_response_gpu/entry98/other16_d0/other16_seed$k \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768_severe.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[120]" --set options.response.label_free=null \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v
