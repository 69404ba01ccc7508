# Sourced by entries 191-195's run.sh: `calibrate_arm CORE OUT FOLD UNIT WRAPPER... -- OPTION...` runs one
# `anytip calibrate` of UNIT with its log, under the network and on the registry its FOLD names (fFOLD:
# fleet88's fold under entry 147's run, on data/val191d; oFOLD: other16's under entry 146's at-120 run, draw
# 0, on data/val191o), pinned to CORE, into OUT; `halves ARMS` runs ARMS (`one CORE ARM FOLD UNIT`, the
# sourcing script's) over units.py's pairs, two at a time. `weighed CORE ARM FOLD UNIT ENTRY BUDGET WEIGHT` is
# one calibration at `--budget-seconds BUDGET` with the log weighed as WEIGHT seconds (entry 190's
# as_asked.py), into build/ENTRY/ARM-FOLD/UNIT (entries 192-195). Entry 201 sets UNITS_PY, REG_D, REG_O and
# USE_LOGS to its own units, registries and logs; entry 215 sets ALONE=1 for the plan alone (no log read).
G=reports/cross_sensor_response_gpu
REG_D=${REG_D:-data/val191d} REG_O=${REG_O:-data/val191o} USE_LOGS=${USE_LOGS:-build/entry191_logs}
mapfile -t pairs < <(python "${UNITS_PY:-$G/entry191/units.py}")
calibrate_arm() {
  local core=$1 out=$2 fold=$3 unit=$4 run=() where
  shift 4
  while [ "$1" != -- ]; do run+=("$1"); shift; done
  shift
  if [ "${fold:0:1}" = f ]; then
    where=(--model $G/entry147/at120/fleet88_seed${fold:1} --registry $REG_D)
  else
    where=(--model $G/entry146/at120/other16_severe_d0/other16_seed${fold:1} --registry $REG_O)
  fi
  local use=(--ordinary-use 600 --use-log "$USE_LOGS/$unit"_o*.h5)
  [ "${ALONE:-0}" = 1 ] && use=()
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" "${run[@]}" calibrate --unit "$unit" --method response \
    --plan-strategy designed "${where[@]}" "${use[@]}" "$@" --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
  echo "$(basename "$(dirname "$out")") $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP ARMS
  local i arm
  for ((i = $2; i < ${#pairs[@]}; i += $3)); do
    for arm in $4; do one "$1" "$arm" ${pairs[$i]}; done
  done
}
halves() {  # ARMS
  half 0 0 2 "$1" & half 1 1 2 "$1"
  wait
}
weighed() {
  calibrate_arm "$1" "build/$5/$2-$3/$4" "$3" "$4" python $G/entry190/as_asked.py "$7" -- \
    --budget-seconds "$6"
}
