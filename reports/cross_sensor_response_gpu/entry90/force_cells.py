"""`scripts/rescore_response.py` with `cover_informative`'s cells kept to one force level (research log
entry 92): a candidate press joins the cell of its nearest `cover` press only where its mean |F| lies
within a factor BAND of that press's (the fingertip's first three targets are the force; the summaries
scale them alike, so the ratio is the force's). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry90/force_cells.py RUN --registry REG --out OUT \\
        [rescore_response.py's options]
"""

import runpy
import sys

import numpy as np

import anytip.data.plans as plans

BAND = 1.25  # a press of |F| between |F_cell| / BAND and |F_cell| x BAND
nearest = plans._cells


def force_cells(presses, chosen):
    """`plans._cells`, less the candidates whose mean |F| is more than BAND away from their cell's press."""
    cell = nearest(presses, chosen)
    force = np.linalg.norm(presses.summary[:, :3], axis=1)
    own = force[np.asarray(chosen)[np.maximum(cell, 0)]]
    near = (force <= own * BAND) & (force >= own / BAND)
    return np.where(near, cell, -1)


plans._cells = force_cells
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
