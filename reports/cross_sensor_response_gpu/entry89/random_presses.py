"""`scripts/rescore_response.py` with every plan-calibrated job's codes fitted on FACTOR times its plan's
press count of whole presses drawn at random from its unit's whole calibration outside its test
patches (research log entry 89), counted as the plan's effective rows per row. The unit's network still
trains on the plan's rows and the rows transferred with those codes. No robot time is priced: a
diagnostic, never a method. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry89/random_presses.py FACTOR RUN --registry REG \\
        --out OUT [rescore_response.py's options]
"""

import runpy
import sys
import zlib
from dataclasses import replace

import numpy as np
import torch

import anytip.pipelines.cross_sensor_response as pipe
from anytip.train.response import fit_codes

if len(sys.argv) < 3 or not sys.argv[1].isdigit():
    sys.exit(__doc__)
FACTOR = int(sys.argv.pop(1))
CODE_ROWS = 16384
planned = pipe.calibrated


def drawn_rows(presses, count: int, unit: str, seed: int) -> np.ndarray:
    """The rows of `count` whole presses drawn without replacement (seeded by the unit and seed)."""
    rng = np.random.default_rng([zlib.crc32(unit.encode()), seed])
    picked = rng.choice(len(presses), size=min(count, len(presses)), replace=False)
    return np.concatenate([presses.rows_of(int(k)) for k in np.sort(picked)])


def random_codes(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes=None, extra=None):
    """`calibrated`, its jobs' codes (where not given) from random whole presses of their units."""
    if codes is None:
        rows = [drawn_rows(sd.evals[u].presses, FACTOR * p.presses, u, seed) for u, _, p in jobs]
        X = [torch.from_numpy(arrays.pressure[r]) for r in rows]
        Y = [torch.from_numpy(arrays.targets[r]) for r in rows]
        n_eff = [p.n_effective * len(r) / len(p.rows) for (_, _, p), r in zip(jobs, rows, strict=True)]
        codes = fit_codes(fit, X, Y, n_eff, replace(recipe, code_rows=CODE_ROWS), seed)
        print(f"random presses: {FACTOR} x the plan's, {min(map(len, rows))}-{max(map(len, rows))} rows",
              flush=True)
    return planned(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes, extra)


pipe.calibrated = random_codes
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
