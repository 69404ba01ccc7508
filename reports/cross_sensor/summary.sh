#!/bin/bash
# The consolidated cross-sensor reports in this directory, written from committed runs alone (no
# training, no registry): pooled folds (`anytip report RUN RUN ... --out DIR`) and comparisons
# (`anytip compare LABEL=RUN[,RUN...][#METHOD] ... --out DIR`). Run from the repository root with
# the virtual environment active (`. .venv/bin/activate`):
#   bash reports/cross_sensor/summary.sh
set -euo pipefail
R=reports/cross_sensor
folds() {  # folds DIR PREFIX N: DIR/PREFIX0,...,DIR/PREFIX<N-1>
  local out=() k
  for ((k = 0; k < $3; k++)); do out+=("$1/$2$k"); done
  (IFS=,; echo "${out[*]}")
}
pool() {  # pool OUT DIR PREFIX N
  # shellcheck disable=SC2046
  anytip report $(folds "$2" "$3" "$4" | tr , ' ') --out "$R/$1" --force
}
f88() { folds "reports/$1" fleet88_seed 2; }
o16() { folds "reports/$1" other16_seed 4; }

# fleet88 (88 pre-registered held-out units, two folds) and other16 (another elastomer, every unit
# held out once, four folds)
pool fleet88_budgets reports/cross_sensor_budgets fleet88_grouped_seed 2  # plan alone, 10 to 600 s, one fleet per budget (entry 79)
pool fleet88_use reports/cross_sensor_response_label_free fleet88_seed 2  # with 600 s of ordinary use
pool fleet88_use60 reports/cross_sensor_budgets fleet88_use60_seed 2      # 60 s, with ordinary use (entry 76)
pool fleet88_use30 reports/cross_sensor_budgets fleet88_use30_seed 2      # 30 s, with ordinary use (entry 77)
pool fleet88_gpu reports/cross_sensor_response_gpu/entry52 fleet88_seed 2 # 1,024 simulated units
pool fleet88_designed reports/cross_sensor_response_gpu/entry58 fleet88_seed 2  # designed plan beside cover
pool other16_budgets reports/cross_sensor_budgets other16_grouped_seed 4  # plan alone, 30 to 600 s, one fleet per budget (entry 79)
pool other16_use reports/cross_sensor_response_label_free/other16_use other16_seed 4
pool other16_gpu reports/cross_sensor_response_gpu/entry54/b512e60 other16_seed 4
pool other16_gpu_wide reports/cross_sensor_response_gpu/entry80 other16_seed 4  # 1,024 units at twice the spread (entry 80)
pool other16_budgets_use reports/cross_sensor_budgets other16_use_grouped_seed 4  # 10 to 120 s, with ordinary use, one fleet per budget (entries 75, 79)

anytip compare --force --out $R/recipe \
  --title "The 2-minute recipe, one ingredient added at a time (fleet88, 88 pre-registered held-out units)" \
  "adapters (input_affine+film) on the same plans=$(folds reports/cross_sensor_response88 seed 2)#adapted:input_affine+film[4000 steps]@cover" \
  "response transfer, 16 registry units (entry 22)=$(folds reports/cross_sensor_response88 seed 2)#response@cover" \
  "+ Gauss-Newton codes, 40-epoch network (entry 24)=$(f88 cross_sensor_response_rescored)#response@cover" \
  "+ 128 simulated units in the response model (entry 25)=$(f88 cross_sensor_response_extra)#response@cover" \
  "+ network started from the pooled network (entry 26)=$(f88 cross_sensor_response_start)#response@cover" \
  "+ 600 s of ordinary use in the codes' fit (entry 46)=$(f88 cross_sensor_response_label_free)#response+use@cover" \
  "+ 1,024 simulated units, GPU (entries 48, 52)=$(f88 cross_sensor_response_gpu/entry52)#response+use@cover"

anytip compare --force --out $R/recipe_other16 \
  --title "The 2-minute recipe, one ingredient added at a time (other16, every unit held out once)" \
  "adapters (input_stats), label-free=$(folds reports/cross_sensor_response_folds16 seed 4)#adapted:input_stats" \
  "response transfer, 10 registry units (entry 23)=$(folds reports/cross_sensor_response_folds16 seed 4)#response@cover" \
  "+ Gauss-Newton codes, 40-epoch network (entry 24)=$(o16 cross_sensor_response_rescored)#response@cover" \
  "+ 128 simulated default-fingertip units (entry 25)=$(o16 cross_sensor_response_extra)#response@cover" \
  "+ network started from the pooled network (entry 26)=$(o16 cross_sensor_response_start)#response@cover" \
  "+ 600 s of ordinary use in the codes' fit (entry 46)=$(o16 cross_sensor_response_label_free/other16_use)#response+use@cover" \
  "+ 1,024 simulated units, GPU (entry 51)=$(o16 cross_sensor_response_gpu/entry51)#response+use@cover" \
  "+ the unit's network in batches of 512, 60 epochs (entry 54)=$(o16 cross_sensor_response_gpu/entry54/b512e60)#response+use@cover" \
  "+ the 1,024 units drawn at twice the spread (entry 80)=$(o16 cross_sensor_response_gpu/entry80)#response+use@cover"

S=reports/cross_sensor_response_severity
anytip compare --force --out $R/severity \
  --title "Response transfer by unit-to-unit spread (fleet24's seed and split, 6 held-out units; entries 32, 34)" \
  "severity 0.5=$S/severity0.5" "severity 1=reports/cross_sensor_response_start/fleet24_seed1" \
  "severity 2=$S/severity2" "severity 2, extra units drawn at 2=$S/severity2_extra2"

anytip compare --force --out $R/units \
  --title "Response transfer by the units its response model learnt (fleet88 fold 0, 44 held-out units; entry 31)" \
  "16 registry + 128 simulated units=reports/cross_sensor_response_start/fleet88_seed0" \
  "16 registry + 1,024 simulated units (GPU)=reports/cross_sensor_response_gpu/rescored_fleet88_seed0_extra1024_rps32768"

# Today's recipe by robot time (entries 153-154), against entry 26's recipe: one series per method from 10 to
# 600 s, joining the runs that measured its budgets on the same units and references.
by_robot_time() {  # by_robot_time OUT TITLE CI CI600 D D120 D600 [ENTRY...]
  # `cover_informative` from CI (10-120 s, entry 153) and CI600 (600 s); the designed plan from D (30-60 s,
  # entry 154), D120 and D600 (entry 146); each a comma-joined list of folds; then further entries as given
  local out=$1 title=$2 ci="$3,$4" designed="$5,$6,$7"
  shift 7
  anytip compare --force --out "$R/$out" --title "$title" \
    "the plan alone=$ci#response@cover_informative" \
    "with 600 s of ordinary use=$ci#response+use@cover_informative" \
    "the designed plan alone=$designed#response@designed" \
    "the designed plan with ordinary use=$designed#response+use@designed" "$@"
}
G=cross_sensor_response_gpu
by_robot_time budgets_recipe \
  "Today's recipe by robot time (fleet88, 88 pre-registered held-out units; entries 153-154)" \
  "$(f88 $G/entry153)" "$(f88 $G/entry143)" "$(f88 $G/entry154)" "$(f88 $G/entry146/at120)" "$(f88 $G/entry146/at600)" \
  "entry 26's recipe, the plan alone (entry 79)=$(folds reports/cross_sensor_budgets fleet88_grouped_seed 2)#response@cover"

D0=other16_severe_d0
by_robot_time budgets_recipe_other16 \
  "Today's recipe by robot time (other16, every unit held out once, start draw 0; entries 153-154)" \
  "$(o16 $G/entry153/$D0)" "$(o16 $G/entry142/$D0)" "$(o16 $G/entry154/$D0)" "$(o16 $G/entry146/at120/$D0)" \
  "$(o16 $G/entry146/at600/$D0)" \
  "entry 26's recipe, the plan alone (entry 79)=$(folds reports/cross_sensor_budgets other16_grouped_seed 4)#response@cover" \
  "entry 26's recipe with ordinary use, 1,034-unit models (entry 79)=$(folds reports/cross_sensor_budgets other16_use_grouped_seed 4)#response+use@cover"

# Today's recipe with each of its steps taken out in turn, at 30 and 120 s, the plan alone (entry 155)
E=$G/entry155
anytip compare --force --out $R/ablation_recipe \
  --title "Today's recipe, each step taken out in turn (fleet88, 88 pre-registered held-out units, the plan alone; entry 155)" \
  "today's recipe=$(f88 $E/all)#response@cover_informative" \
  "without the exchange (cover)=$(f88 $E/all)#response@cover" \
  "without the registry code prior=$(f88 $E/prior)#response@cover_informative" \
  "without the converged code fit=$(f88 $E/fit)#response@cover_informative" \
  "without the residual correction=$(f88 $E/residual)#response@cover_informative"
