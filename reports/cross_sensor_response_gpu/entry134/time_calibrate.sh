#!/bin/bash
# Research log entry 134: `anytip calibrate --ordinary-use 600` at 120 s (`cover_informative`, fleet88 fold 0's
# CPU response model of entry 106's run), one core (taskset -c 1, the other core idle), the correction kept
# (the model as saved, which records no `residual_level`) alternated with the same model copied under
# build/ with `residual_level: centred` written into its recipe, $1 rounds (default 3) over the units named
# after it (default entry 116's three). Prints each calibration's `wall_s` (fit and fold) and the command's
# seconds.
rounds=${1:-3}; shift; units=${*:-SIM40-000 SIM40-001 SIM40-002}
G=reports/cross_sensor_response_gpu
kept=$G/entry106/fleet88_cpu_use/fleet88_seed0; centred=build/entry134_centred/fleet88_seed0
rm -rf $centred && mkdir -p $(dirname $centred) && cp -r $kept $centred
python - "$centred/models/response_seed0.json" <<'PY'
import json, sys
path = sys.argv[1]
model = json.load(open(path))
model["meta"]["recipe"]["residual_level"] = "centred"
json.dump(model, open(path, "w"))
PY
TIMING_DIR=time_calibrate134; . $G/entry116/time_one.sh
for r in $(seq $rounds); do
  for unit in $units; do
    time_one kept $unit $r $kept --ordinary-use 600
    time_one centred $unit $r $centred --ordinary-use 600
  done
done
