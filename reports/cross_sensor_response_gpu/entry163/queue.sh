#!/bin/bash
# Entry 163's six jobs, two at a time, once entry 162's queue (if running) has ended; logs in entry163/logs.
#   bash reports/cross_sensor_response_gpu/entry163/queue.sh
set -uo pipefail
E=reports/cross_sensor_response_gpu/entry163
mkdir -p $E/logs
while pgrep -f entry162/queue.sh > /dev/null; do sleep 20; done
for pair in "0:32 1:0" "2:0 2:32" "3:0 3:32"; do
  for job in $pair; do
    k=${job%:*} from=${job#*:}
    /usr/bin/time -v bash $E/run.sh $k $from > $E/logs/rows_k${k}_from$from.log 2>&1 &
  done
  wait
done
