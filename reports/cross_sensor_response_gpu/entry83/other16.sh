# Sourced by the rescoring scripts of research log entries 83-85 (not run alone).
# other16_rescore FOLD MODEL EPOCHS OUT SCRIPT [SCRIPT_ARGS...]: other16 fold FOLD rescored as entry
# 81's 10-step arm did (today's recipe: budgets 0 and 120 s, ordinary use, the units' networks in
# batches of 512 at lr 0.02 for EPOCHS epochs), with the response models MODEL (`{seed}`: the fold's),
# by SCRIPT (a wrapper of scripts/rescore_response.py, given SCRIPT_ARGS first), into OUT.
DEFAULT_SPREAD='reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors'
TWICE_THE_SPREAD='reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768_severe.safetensors'

other16_rescore() {
  local k=$1 model=$2 epochs=$3 out=$4 script=$5
  shift 5
  python "$script" "$@" reports/cross_sensor_response_start/other16_seed$k --registry data/other16 \
    --response-model "$model" \
    --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
    --set "options.response.label_free={with_plans: true, zero_shot: false}" \
    --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
    --set options.response.inverse_epochs=$epochs \
    --out "$out"
}
