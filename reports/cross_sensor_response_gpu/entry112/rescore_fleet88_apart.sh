#!/bin/bash
# Research log entry 112: entry 110's rescoring of fold $1 with today's code (data/fleet88r, every unit tested
# on both its sessions, `splits.test_rows: all_sessions`), where the validation and factor units are calibrated
# in fleets of their own, apart from the held-out units (`fleet_groups`), into entry112/fleet88r_apart. Its
# control is entry110/fleet88r_both: the same rescoring from the code before, which calibrated the validation
# and held-out units in one fleet per budget.
[ $# -eq 1 ] || { echo "usage: $0 FOLD" >&2; exit 2; }
bash reports/cross_sensor_response_gpu/entry108/rescore_fleet88_retest.sh "$1" entry112/fleet88r_apart \
  --set splits.test_rows=all_sessions
