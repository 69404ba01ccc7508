#!/bin/bash
# Research log entry 48: fleet88 fold 1's and other16's four folds' response models with 1,024 extra
# units at 32,768 rows a step, the extra units simulated once. Needs .whl (pydantic and its needs).
date; nvidia-smi -L
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
    > $OUT/setup.txt 2>&1 || { cat $OUT/setup.txt; exit 1; }
export PYTHONPATH=/tmp/site:$PWD/research OMP_NUM_THREADS=1 PYTHONUNBUFFERED=1
python3 -c "import anytip.pipelines.cross_sensor, h5py, safetensors, torch, numpy; print(torch.__version__, numpy.__version__)" || exit 1
R=reports/cross_sensor_response_extra; S=scripts/response_many_units.py; X=/tmp/extra1024; M=$OUT/m; mkdir -p $M
T=${LIMIT:-540}
timeout $T python3 $S $R/fleet88_seed1 --registry-seed 40 --models 1024:32768 --workers 16 --device cuda \
    --extra-store $X --out $M > $OUT/a.txt 2>&1 &
A=$!
# other16 starts once the extra units are stored, reading them while fleet88's model trains
until grep -q "^simulated" $OUT/a.txt 2>/dev/null || ! kill -0 $A 2>/dev/null; do sleep 2; done
timeout $((T - SECONDS + 5)) python3 $S $R/other16_seed0 $R/other16_seed1 $R/other16_seed2 $R/other16_seed3 \
    --registry-seed 23 --registry-fleet configs/fleets/other_elastomer.yaml --models 1024:32768 --workers 16 \
    --device cuda --extra-store $X --out $M > $OUT/b.txt 2>&1 &
wait
date; cd $OUT && tar cf models.tar m && rm -rf m; ls -la $OUT
