#!/bin/bash
# Research log entry 51: other16 folds 2-3's response models with 1,024 extra units at 32,768 rows a
# step, the extra units' rows split with seed 0 as entry 48's call for folds 0-3 split them.
# Needs .whl (pydantic and its needs).
date; nvidia-smi -L
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
    > $OUT/setup.txt 2>&1 || { cat $OUT/setup.txt; exit 1; }
export PYTHONPATH=/tmp/site:$PWD/research OMP_NUM_THREADS=1 PYTHONUNBUFFERED=1
python3 -c "import anytip.pipelines.cross_sensor, h5py, safetensors, torch, numpy; print(torch.__version__, numpy.__version__)" || exit 1
R=reports/cross_sensor_response_extra
timeout ${LIMIT:-540} python3 scripts/response_many_units.py $R/other16_seed2 $R/other16_seed3 \
    --registry-seed 23 --registry-fleet configs/fleets/other_elastomer.yaml --models 1024:32768 \
    --extra-split-seed 0 --workers 16 --device cuda --out $OUT/m 2>&1 | tee $OUT/stdout.txt
date; ls -la $OUT $OUT/m
