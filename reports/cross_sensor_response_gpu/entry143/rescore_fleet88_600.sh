#!/bin/bash
# Research log entry 143: entry 122's fleet88 rescoring of fold $1 (today's recipe: the CPU response models, the
# registry code prior, the converged code fit, criterion v, the plan's residual correction centred with ordinary
# use) at 600 s on data/fleet88f (entry 139: fleet88p plus the chosen 600 s design's plan600), `cover_informative`
# and `designed` side by side, alone and with 600 s of ordinary use, into entry143/fleet88_seed$1.
REGISTRY=data/fleet88f exec bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 entry143 \
  --added-protocol plan120 --added-protocol plan600 --set "data.protocol=[full, short, quick, plan120, plan600]" \
  --set "options.plan_strategies=[cover_informative, designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[600]"
