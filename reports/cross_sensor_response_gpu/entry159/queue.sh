#!/bin/bash
# Entry 159's four folds, two at a time, as entry 158's queue runs them; logs in entry159/logs.
#   bash reports/cross_sensor_response_gpu/entry159/queue.sh
exec bash reports/cross_sensor_response_gpu/entry158/queue.sh reports/cross_sensor_response_gpu/entry159
