"""`scripts/rescore_response.py` with each new unit's network trained with a warm-up of FRACTION of
its steps (the fast recipe's one-cycle warms up over 0.15 of them from lr / 25) (research log entry
85). The pooled start network, trained from random weights, keeps the recipe's warm-up. Usage, from
the repository root:

    python reports/cross_sensor_response_gpu/entry85/warmup.py FRACTION RUN --registry REG --out OUT \\
        [rescore_response.py's options]
"""

import runpy
import sys

import anytip.train.response as response

try:
    FRACTION = float(sys.argv.pop(1))
except (IndexError, ValueError):
    sys.exit(__doc__)
if not 0 <= FRACTION < 1 or len(sys.argv) < 2:
    sys.exit(__doc__)
FAST = response.FAST
trained = response.unit_networks


def warmed(rows, shape, recipe, seed, ids, output_names, device, progress, start=None):
    """`unit_networks`, a unit's network (one with a start) warming up over FRACTION of its steps."""
    if start is None:
        return trained(rows, shape, recipe, seed, ids, output_names, device, progress, start)
    response.FAST = FAST.model_copy(update={"warmup_frac": FRACTION})
    try:
        return trained(rows, shape, recipe, seed, ids, output_names, device, progress, start)
    finally:
        response.FAST = FAST


response.unit_networks = warmed
print(f"units' networks warm up over {FRACTION:g} of their steps", flush=True)
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
