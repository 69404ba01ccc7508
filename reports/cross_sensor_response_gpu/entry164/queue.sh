#!/bin/bash
# Entry 164's folds 0 and 1 at once, as entry 161's queue runs them; logs in entry164/logs.
#   bash reports/cross_sensor_response_gpu/entry164/queue.sh
exec bash reports/cross_sensor_response_gpu/entry161/queue.sh reports/cross_sensor_response_gpu/entry164
