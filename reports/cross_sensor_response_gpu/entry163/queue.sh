#!/bin/bash
# Entry 163's six jobs, two at a time, once entry 162's queue (if running) has ended; logs in entry163/logs.
# Entry 166 runs its jobs through it, naming its directory, the queue it waits for, its logs' prefix and its
# (fold:slice) pairs, each pair's two jobs at once:
#   bash reports/cross_sensor_response_gpu/entry163/queue.sh [DIR WAIT_FOR LOG_PREFIX "K:FROM K:FROM" ...]
set -uo pipefail
E=${1:-reports/cross_sensor_response_gpu/entry163} wait_for=${2:-entry162/queue.sh} prefix=${3-rows_}
pairs=("${@:4}")
[ ${#pairs[@]} -gt 0 ] || pairs=("0:32 1:0" "2:0 2:32" "3:0 3:32")
mkdir -p $E/logs
# WAIT_FOR after a slash: the awaited queue runs by its path, while this queue holds WAIT_FOR as an argument
# after a space, so it never waits for itself
while pgrep -f "/$wait_for" > /dev/null; do sleep 20; done
for pair in "${pairs[@]}"; do
  for job in $pair; do
    k=${job%:*} from=${job#*:}
    /usr/bin/time -v bash $E/run.sh $k $from > $E/logs/${prefix}k${k}_from$from.log 2>&1 &
  done
  wait
done
