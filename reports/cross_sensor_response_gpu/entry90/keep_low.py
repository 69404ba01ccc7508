"""`scripts/rescore_response.py` with `cover_informative`'s low-force presses kept (research log entry 93):
a `cover` press whose mean |F| lies below the lower quartile of the unit's candidate presses' is never
exchanged; the others are, across force levels, as entry 91's (the fingertip's first three targets are
the force). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry90/keep_low.py [WRAPPER.py WRAPPER_ARGS] RUN \\
        --registry REG --out OUT [rescore_response.py's options]

A first argument ending in `.py` is another wrapper of `scripts/rescore_response.py` (entry 83's
`start_draw.py`), run with the rest of the arguments and this selection in place.
"""

import runpy
import sys

import numpy as np

import anytip.data.plans as plans

nearest = plans._cells


def keep_low(presses, chosen):
    """`plans._cells`, with the cells of the low-force `cover` presses emptied (those presses stay)."""
    cell = nearest(presses, chosen)
    force = np.linalg.norm(presses.summary[:, :3], axis=1)
    low = np.flatnonzero(force[np.asarray(chosen)] < np.quantile(force, 0.25))
    return np.where(np.isin(cell, low), -1, cell)


plans._cells = keep_low
RESCORE = "scripts/rescore_response.py"
script = sys.argv.pop(1) if len(sys.argv) > 1 and sys.argv[1].endswith(".py") else RESCORE
sys.argv[0] = script
runpy.run_path(script, run_name="__main__")
