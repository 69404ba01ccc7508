#!/bin/bash
# Research log entry 168 (b): entry 134's timing of `anytip calibrate` at 120 s (`cover_informative`, fleet88 fold
# 0's CPU response model of entry 106's run, data/fleet88, one core: taskset -c 1 with the other core idle), the
# plan alone and with 600 s of ordinary use, on entry 116's three units, $1 rounds (default 3). Each calibration
# runs with today's code and with entry 134's commit (c401b544, a worktree under build/) in turn, the order
# alternating by round. Prints 'ARM CODE UNIT round R wall_s S command_s C' per calibration (wall_s: fit and fold).
#   bash reports/cross_sensor_response_gpu/entry168/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry168/logs/time_calibrate.log
set -euo pipefail
rounds=${1:-3}
root=$(pwd) old=$(pwd)/build/entry168_c401b544 out=$(pwd)/build/time_calibrate168
run=$root/reports/cross_sensor_response_gpu/entry106/fleet88_cpu_use/fleet88_seed0
[ -d "$old" ] || git worktree add -q "$old" c401b544
export OMP_NUM_THREADS=1
one() {  # CODE ARM UNIT ROUND
  local code=$1 arm=$2 unit=$3 r=$4 dir use=()
  [ "$code" = today ] && dir=$root || dir=$old
  [ "$arm" = use ] && use=(--ordinary-use 600)
  local to=$out/${code}_${arm}_${unit}_$r
  rm -rf "$to"; mkdir -p "$out"
  local start=$(date +%s.%N)
  (cd "$dir" && PYTHONPATH=research taskset -c 1 python -m anytip.cli calibrate --model "$run" --unit "$unit" \
    --registry "$root/data/fleet88" --budget-seconds 120 --method response --plan-strategy cover_informative \
    "${use[@]}" --out "$to" > "$to.log" 2>&1) || { cat "$to.log"; exit 1; }
  local end=$(date +%s.%N)
  python -c "import json; c=json.load(open('$to/calibration.json')); print('$arm $code $unit round $r', 'wall_s %.2f' % c['wall_s'], 'command_s %.1f' % ($end - $start))"
}
. "$root/reports/cross_sensor_response_gpu/entry116/time_one.sh"
alternated "$rounds" today entry134
