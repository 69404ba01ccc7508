#!/bin/bash
# Research log entry 208: the two simulated designs other than the fingertip, 24 registry units (full and
# short protocols) and 128 training-only units (full) each, fresh seeds no earlier entry used.
set -euo pipefail
anytip data simulate --registry data/edge24 --units 24 --seed 31 --protocols full,short --sensor-model edge-4baro
anytip data simulate --registry data/edge_extra128 --units 128 --seed 33 --protocols full --sensor-model edge-4baro
anytip data simulate --registry data/pad24 --units 24 --seed 32 --protocols full,short --sensor-model pad-16baro
anytip data simulate --registry data/pad_extra128 --units 128 --seed 34 --protocols full --sensor-model pad-16baro
# Research log entry 210: the edge units again, each with its designed calibrations of 30, 120 and 600 s
# (`anytip calibrate --plan S --sensor-model edge-4baro --plan-points halton`, run after its full and short runs;
# Halton points were the flat designs' default until entry 214).
anytip data simulate --registry data/edge24p --units 24 --seed 31 --protocols full,short,plan30,plan120,plan600 \
  --sensor-model edge-4baro --plan-points halton
# Research log entry 211: the same units, their designed plans of 30, 60, 120 and 600 s run with 0.4 s moves
# (the full protocol's), the plans of 30, 120 and 600 s at entry 210's points (the same run seeds).
anytip data simulate --registry data/edge24f --units 24 --seed 31 \
  --protocols full,short,plan30,plan120,plan600,plan60 --sensor-model edge-4baro --move-s 0.4 --plan-points halton
# Research log entry 212: the same units, their designed plans' points drawn at random (`--plan-points random`).
anytip data simulate --registry data/edge24r --units 24 --seed 31 \
  --protocols full,short,plan30,plan120,plan600,plan60 --sensor-model edge-4baro --move-s 0.4 --plan-points random
# Research log entry 217: the pad's units again (data/pad24's full and short runs), each with its designed
# calibrations of 30, 120 and 600 s at the flat designs' default points (random, entry 214) and 2 s moves, run
# after its full and short runs.
anytip data simulate --registry data/pad24p --units 24 --seed 32 --protocols full,short,plan30,plan120,plan600 \
  --sensor-model pad-16baro
