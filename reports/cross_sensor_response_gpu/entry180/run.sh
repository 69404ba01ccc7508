#!/bin/bash
# Research log entry 180: entry 178's 16 units calibrated with `--use-log`: each unit's `use` runs of data/use178
# written as ordinary-use logs (pressures alone) under build/entry180_logs/, then calibrate reads them as its
# ordinary use (arm L, build/entry178/L/). Two units at a time, one per core; about 4 minutes.
#   bash reports/cross_sensor_response_gpu/entry180/run.sh > reports/cross_sensor_response_gpu/entry180/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
model=$G/entry147/at120/fleet88_seed0
units=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
python - <<'PY'
from pathlib import Path
from anytip.data.registry import Registry
from anytip.data.use_log import UseLog, write_use_log
registry, out = Registry("data/use178"), Path("build/entry180_logs")
out.mkdir(parents=True, exist_ok=True)
for record in registry.list_runs():
    if record.protocol == "use":
        r = registry.open_run(record.run_id)
        log = UseLog.of_run(r)
        write_use_log(log, out / f"{record.run_id}.h5")
PY
half() {  # CORE FIRST STEP
  for ((i = $2; i < ${#units[@]}; i += $3)); do
    local unit=${units[$i]} out=build/entry178/L/${units[$i]}
    rm -rf "$out"; mkdir -p "$(dirname "$out")"
    OMP_NUM_THREADS=1 taskset -c "$1" anytip calibrate --model $model --unit "$unit" --registry data/use178 \
      --budget-seconds 120 --method response --plan-strategy designed --ordinary-use 600 \
      --use-log build/entry180_logs/"$unit"_*.h5 --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
    echo "L $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
  done
}
half 0 0 2 & half 1 1 2
wait
