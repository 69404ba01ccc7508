#!/bin/bash
# Research log entry 80: other16's response models with 1,024 extra units drawn at twice the default
# spread (configs/fleets/severe.yaml, the same seed-8 draws as entries 48 and 51), at 32,768 rows a
# step, the extra units' rows split with seed 0 as entry 48's call for the four folds split them.
# Usage: device_call.sh K [K ...]  (other16 folds). The extra units are kept in build/extra_severe and a
# second call on the same machine reads them instead of simulating them again. Needs .whl (pydantic
# and its needs).
date; nvidia-smi -L
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
    > $OUT/setup.txt 2>&1 || { cat $OUT/setup.txt; exit 1; }
export PYTHONPATH=/tmp/site:$PWD/research OMP_NUM_THREADS=1 PYTHONUNBUFFERED=1
python3 -c "import anytip.pipelines.cross_sensor, h5py, safetensors, torch, numpy; print(torch.__version__, numpy.__version__)" || exit 1
R=reports/cross_sensor_response_extra
timeout ${LIMIT:-540} python3 scripts/response_many_units.py $(for k in "$@"; do echo $R/other16_seed$k; done) \
    --registry-seed 23 --registry-fleet configs/fleets/other_elastomer.yaml --models 1024:32768 \
    --extra-fleet configs/fleets/severe.yaml --extra-split-seed 0 --extra-store build/extra_severe \
    --workers 16 --device cuda --out $OUT/m 2>&1 | tee $OUT/stdout_$(echo "$@" | tr ' ' _).txt
date; ls -la $OUT $OUT/m
