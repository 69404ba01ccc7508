#!/bin/bash
# Research log entry 147: data/fleet88h, data/fleet88g (entry 146: fleet88 with each unit's designed calibrations of
# 120, 150, 600 and 750 s) plus each unit's test session (protocol `retest`, as entry 108's data/fleet88r), simulated
# with the registry's own protocols first, so every run already there is added again unchanged.
#   bash reports/cross_sensor_response_gpu/entry147/make_registry.sh
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
rm -rf data/fleet88h.tmp
cp -a data/fleet88g data/fleet88h.tmp
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry data/fleet88h.tmp --units 88 --seed 40 --protocols full,short,quick,plan120,plan600,plan150,plan750,retest
rm -rf data/fleet88h; mv data/fleet88h.tmp data/fleet88h
