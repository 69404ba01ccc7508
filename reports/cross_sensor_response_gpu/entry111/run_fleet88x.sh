#!/bin/bash
# Research log entry 111: entry 107's fresh held-out test (entry 106's fold $1, its response model and its 28
# learners) on data/fleet88x, where 64 units never simulated before (SIM43-*) are held out, the first 32
# under fold 0 and the last 32 under fold 1, and every unit with a test session (retest) is tested on both
# its sessions (splits.test_rows=all_sessions; data.protocol names retest, which entry 106's spec leaves out, so
# that the test sessions' runs are read at all), into entry111/fleet88x_seed$1. The first runs, without the
# data.protocol option, read no test session and tested every unit on its main rows alone
# (entry111/one_session_seed$1).
case $1 in 0) units=0:32 ;; 1) units=32:64 ;; *) echo "usage: $0 0|1" >&2; exit 2 ;; esac
python reports/cross_sensor_response_gpu/entry107/fresh_held_out.py \
  reports/cross_sensor_response_gpu/entry106/fleet88_cpu_use/fleet88_seed$1 --registry data/fleet88x \
  --prefix SIM43- --units $units --set splits.test_rows=all_sessions \
  --set "data.protocol=[full, short, quick, retest]" \
  --out reports/cross_sensor_response_gpu/entry111/fleet88x_seed$1
