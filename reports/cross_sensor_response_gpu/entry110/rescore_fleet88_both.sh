#!/bin/bash
# Research log entry 110: entry 108's rescoring of fold $1 (entry 106's recipe with ordinary use and the plan's
# residual correction, fleet88's CPU response models, `cover_informative`, 24 factor units, `data/fleet88r`,
# `--paired-only`) with every unit tested on both its sessions: its main rows at its test patches (entry 106's
# test rows) and its test session's there (entry 108's), `splits.test_rows: all_sessions`. Plans, networks and
# the plans' own half-widths are entry 106's. $2: the output directory under entry110/ (default fleet88r_both);
# entry110/fleet88r_both_f64 was run from a checkout of the commit before entry 109's float32 kernel (1111cd4)
# with `splits.test_rows` and these two scripts applied, whose networks are entry 106's.
[ $# -ge 1 ] && [ $# -le 2 ] || { echo "usage: $0 FOLD [OUTDIR]" >&2; exit 2; }
bash reports/cross_sensor_response_gpu/entry108/rescore_fleet88_retest.sh "$1" "entry110/${2:-fleet88r_both}" \
  --set splits.test_rows=all_sessions
