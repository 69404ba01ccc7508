#!/bin/bash
# Research log entry 139's tables (logs/analyse.log):  bash reports/cross_sensor_response_gpu/entry139/analyse.sh
set -uo pipefail
export PYTHONPATH=research
e=reports/cross_sensor_response_gpu/entry139
table() { echo "== $*"; python scripts/fold_table.py "$@" 2>&1 | grep -v '^|---' ; echo; }
for reg in other16 fleet88; do
  n=$([ $reg = other16 ] && echo 3 || echo 1)
  runs() { for k in $(seq 0 $n); do echo "$e/$1_seed$k"; done; }
  grouped=$(for k in $(seq 0 $n); do echo "reports/cross_sensor_budgets/${reg}_grouped_seed$k"; done)
  [ -f "$e/${reg}_seed$n/metrics.json" ] || continue
  table $(runs $reg)
  table $(runs $reg) --against $grouped                      # the gate: cover against entry 79
  table $(runs $reg) --strategies designed cover
  for arm in ${reg}s ${reg}f ${reg}sf; do
    [ -f "$e/${arm}_seed$n/metrics.json" ] || continue
    table $(runs $arm) --strategies designed cover
  done
  [ -f "$e/${reg}s_seed$n/metrics.json" ] && table $(runs ${reg}s) --against $(runs $reg)   # without sessions over with
  [ -f "$e/${reg}f_seed$n/metrics.json" ] && table $(runs ${reg}f) --against $(runs $reg)   # the variant over the design in place
  [ -f "$e/${reg}sf_seed$n/metrics.json" ] && table $(runs ${reg}sf) --against $(runs ${reg}s)
done
python - <<'PY'
import json, glob
import numpy as np
print("== validation units' mean loss at 600 s (models/response_seed*.json), held-out robot time and presses")
e = "reports/cross_sensor_response_gpu/entry139"
for arm in ["other16", "other16f", "other16s", "other16sf", "fleet88", "fleet88f"]:
    files = sorted(glob.glob(f"{e}/{arm}_seed*/metrics.json"))
    if not files:
        continue
    rows = [r for f in files for r in json.load(open(f))["results"]]
    models = [json.load(open(f))["meta"] for f in sorted(glob.glob(f"{e}/{arm}_seed*/models/response_seed*[0-9].json"))]
    for strat in ("designed", "cover"):
        mine = [r for r in rows if r["method"] == f"response@{strat}"]
        val = np.mean([m["val_loss_by_strategy"][strat]["600"] for m in models])
        cs, pr = [r["calib_seconds"] for r in mine], [r["presses"] for r in mine]
        print(f"{arm:10s} {strat:9s} validation loss {val:.5f} over {len(models)} folds; {len(mine)} held-out rows, "
              f"robot time {min(cs):.0f}-{max(cs):.0f} s, presses {min(pr)}-{max(pr)}")
PY
