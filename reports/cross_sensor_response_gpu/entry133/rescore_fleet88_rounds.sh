#!/bin/bash
# Research log entry 133: entry 122's fleet88 rescoring of fold $1 (data/fleet88p, the recipe with the centred
# correction, ordinary use, designed and cover_informative) with entry 132's variant in its `rounds` arm (every
# joint fit with ordinary use starts from the search's rounds from the plan's own codes), into
# entry133/fleet88_seed$1. Run from the root of a worktree of the entry's commit with entry132/variant.patch
# applied.
E132_START=rounds exec bash reports/cross_sensor_response_gpu/entry122/rescore_fleet88_designed_use.sh "$1" entry133
