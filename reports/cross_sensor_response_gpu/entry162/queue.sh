#!/bin/bash
# Entry 162's twelve jobs, two at a time: the rows of the six (fold, slice) pairs that entry 158 did not run,
# then their references; logs in entry162/logs.
#   bash reports/cross_sensor_response_gpu/entry162/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry162
mkdir -p $E/logs
for what in rows references; do
  for pair in "0:32 1:0" "2:0 2:32" "3:0 3:32"; do
    for job in $pair; do
      k=${job%:*} from=${job#*:}
      /usr/bin/time -v bash $E/run.sh $what $k $from > $E/logs/${what}_k${k}_from$from.log 2>&1 &
    done
    wait
  done
done
