#!/bin/bash
# Research log entry 131: entry 122's fleet88 rescoring of fold $1 (data/fleet88p, the recipe, ordinary use,
# designed and cover_informative) with entry 130's variant (the correction of every job with ordinary use
# centred per barometer), into entry131/fleet88_seed$1. Run from the root of a worktree of the entry's commit
# with entry130/variant.patch applied.
exec bash reports/cross_sensor_response_gpu/entry122/rescore_fleet88_designed_use.sh "$1" entry131
