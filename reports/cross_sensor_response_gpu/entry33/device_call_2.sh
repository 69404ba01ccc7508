#!/bin/bash
pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl > $OUT/setup.txt 2>&1
export PYTHONPATH=/tmp/site:$PWD/research OMP_NUM_THREADS=1
R=build/dev_runs; S=scripts/response_many_units.py; mkdir -p $OUT/m
timeout 245 python $S $R/fleet88_seed1 --registry-seed 40 --models 128:32768 --workers 8 --device cuda --out $OUT/m > $OUT/a.txt 2>&1 &
timeout 245 python $S $R/other16_seed1 --registry-seed 23 --registry-fleet configs/fleets/other_elastomer.yaml --models 128:32768 --workers 8 --device cuda --out $OUT/m > $OUT/c.txt 2>&1 &
wait
cd $OUT && tar cf models.tar m && rm -rf m
