# Sourced by the timing scripts of research log entries 116, 134, 168 and 172: `time_one LABEL UNIT ROUND RUN
# [OPTION...]` runs `anytip calibrate` at 120 s by response transfer (`cover_informative`) of UNIT on data/fleet88 with the
# response model of RUN and the options after it, on one core (taskset -c 1, OMP_NUM_THREADS=1), into
# build/$TIMING_DIR/LABEL_UNIT_ROUND, and prints its `wall_s` (fit and fold), the whole command's seconds and, where
# the calibration records it (since entry 171), the core's reference product rate `core_gflops`. With CODE (a
# checkout's root, entry 172) the calibration runs that checkout's `research/` instead of the current tree's.
time_one() {
  local arm=$1 unit=$2 r=$3 run=$4; shift 4
  local out=build/$TIMING_DIR/${arm}_${unit}_$r
  rm -rf $out; mkdir -p $(dirname $out)
  local start=$(date +%s.%N)
  local code=${CODE:+$CODE/research}
  PYTHONPATH=${code:-$PYTHONPATH} OMP_NUM_THREADS=1 taskset -c 1 anytip calibrate --model $run --unit $unit --registry data/fleet88 \
    --budget-seconds 120 --method response --plan-strategy cover_informative "$@" --out $out > $out.log 2>&1 \
    || { cat $out.log; exit 1; }
  local end=$(date +%s.%N)
  python -c "import json; c=json.load(open('$out/calibration.json')); g=c.get('core_gflops'); print('$arm $unit round $r', 'wall_s %.2f' % c['wall_s'], 'command_s %.1f' % ($end - $start), *(['core_gflops %.1f' % g] if g else []))"
}

# `alternated ROUNDS A B` calls the caller's `one CODE ARM UNIT ROUND` over ROUNDS rounds of entry 116's three units
# and both arms (the plan alone, with ordinary use), each calibration with code A and with code B in turn, the
# order alternating by round (entries 168 and 172).
alternated() {
  local rounds=$1 a=$2 b=$3 r unit arm code codes
  for r in $(seq "$rounds"); do
    codes="$a $b"; [ $((r % 2)) = 0 ] && codes="$b $a"
    for unit in SIM40-000 SIM40-001 SIM40-002; do
      for arm in alone use; do
        for code in $codes; do one "$code" "$arm" "$unit" "$r"; done
      done
    done
  done
}
