"""`scripts/rescore_response.py` with every plan-calibrated job's codes fitted on its unit's whole
calibration instead of its plan (research log entry 87): every press of the unit's runs outside its
test patches, `ROWS` of their rows evenly spaced, worth as many effective rows per row as the job's
plan. The unit's network still trains on the plan's rows and the rows transferred with those codes.
Knowledge no calibration has: a ceiling, never a method. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry87/oracle_codes.py ROWS RUN --registry REG \\
        --out OUT [rescore_response.py's options]

With `--same-rows` after ROWS it runs `entry101/same_rows.py` instead (a registry simulated again from the
run's own command; entry 119).
"""

import runpy
import sys
from dataclasses import replace

import torch

import anytip.pipelines.cross_sensor_response as pipe
from anytip.train.response import fit_codes

if len(sys.argv) < 3 or not sys.argv[1].isdigit():
    sys.exit(__doc__)
ROWS = int(sys.argv.pop(1))
SAME_ROWS = len(sys.argv) > 1 and sys.argv[1] == "--same-rows"
if SAME_ROWS:
    sys.argv.pop(1)
planned = pipe.calibrated


def oracle(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes=None, extra=None):
    """`calibrated`, its jobs' codes (where not given) from their units' whole calibrations."""
    if codes is None:
        rows = [sd.evals[u].presses.rows for u, _, _ in jobs]
        X = [torch.from_numpy(arrays.pressure[r]) for r in rows]
        Y = [torch.from_numpy(arrays.targets[r]) for r in rows]
        n_eff = [p.n_effective * len(r) / len(p.rows) for (_, _, p), r in zip(jobs, rows, strict=True)]
        codes = fit_codes(fit, X, Y, n_eff, replace(recipe, code_rows=ROWS), seed)
        print(f"oracle codes: {len(jobs)} jobs, {min(map(len, rows))}-{max(map(len, rows))} rows each, "
              f"n_eff {min(n_eff):.0f}-{max(n_eff):.0f}", flush=True)
    return planned(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes, extra)


pipe.calibrated = oracle
script = ("reports/cross_sensor_response_gpu/entry101/same_rows.py" if SAME_ROWS
          else "scripts/rescore_response.py")
sys.argv[0] = script
runpy.run_path(script, run_name="__main__")
