#!/bin/bash
# Research log entry 140's tables (logs/analyse.log):  bash reports/cross_sensor_response_gpu/entry140/analyse.sh
# With a directory of other16_seed{0..3} runs made the same way (entry 142's), its two tables alone.
export PYTHONPATH=research
e=${1:-reports/cross_sensor_response_gpu/entry140/other16_severe_d0}
runs=$(echo $e/other16_seed{0,1,2,3})
python scripts/fold_table.py $runs | grep -v '^|---'
echo
python scripts/fold_table.py $runs --strategies designed cover_informative | tail -1
[ $# -gt 0 ] && exit 0
echo "== against entry 139's 600 s rows (entry 26's recipe): today's recipe over it, per unit"
python - <<'PY'
import json, glob
from anytip.report.cross_sensor import paired_text
e139 = "reports/cross_sensor_response_gpu/entry139/other16_seed"
e140 = "reports/cross_sensor_response_gpu/entry140/other16_severe_d0/other16_seed"
def rows(prefix, method):
    out = {}
    for k in range(4):
        for r in json.load(open(f"{prefix}{k}/metrics.json"))["results"]:
            if r["method"] == method:
                out[r["unit"]] = r["force_rmse_n"]
    return out
for mine, theirs in [("response@designed", "response@designed"), ("response@cover_informative", "response@cover"),
                     ("response+use@designed", "response@designed")]:
    a, b = rows(e140, mine), rows(e139, theirs)
    units = sorted(a)
    print(f"{mine} over entry 139's {theirs}, force:", paired_text([a[u] / b[u] for u in units]))
PY
