#!/bin/bash
# Entry 166's eight (fold, slice) jobs, two at a time, after entry 165's queue: first the six of entry 162's
# (fold, slice) pairs that entry 164 did not run, then folds 2 and 3's own units (entries 158-160); logs in
# entry166/logs.
#   bash reports/cross_sensor_response_gpu/entry166/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry166
mkdir -p $E/logs
while pgrep -f entry165/queue.sh > /dev/null; do sleep 30; done
for pair in "0:32 1:0" "2:0 2:32" "3:0 3:32" "2:64 3:96"; do
  for job in $pair; do
    k=${job%:*} from=${job#*:}
    /usr/bin/time -v bash $E/run.sh $k $from > $E/logs/k${k}_from$from.log 2>&1 &
  done
  wait
done
