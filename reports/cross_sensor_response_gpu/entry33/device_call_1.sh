#!/bin/bash
date; nvidia-smi -L; python --version
pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl > $OUT/setup.txt 2>&1
export PYTHONPATH=/tmp/site:$PWD/research OMP_NUM_THREADS=1
python -c "import h5py, safetensors, torch, numpy; print(torch.__version__, numpy.__version__)"
R=build/dev_runs; S=scripts/response_many_units.py; mkdir -p $OUT/m
timeout 465 python $S $R/fleet88_seed1 --registry-seed 40 --models 1024:32768 --workers 11 --device cuda --out $OUT/m > $OUT/b2.txt 2>&1 &
timeout 465 python $S $R/fleet88_seed0 $R/fleet88_seed1 --registry-seed 40 --models 128:32768 --workers 3 --device cuda --out $OUT/m > $OUT/ab1.txt 2>&1 &
timeout 465 nice -n 19 python $S $R/other16_seed0 $R/other16_seed1 $R/other16_seed2 $R/other16_seed3 --registry-seed 23 --registry-fleet configs/fleets/other_elastomer.yaml --models 128:32768 --workers 4 --device cuda --out $OUT/m > $OUT/c.txt 2>&1 &
wait
date; cd $OUT && tar cf models.tar m && rm -rf m; ls -la $OUT
