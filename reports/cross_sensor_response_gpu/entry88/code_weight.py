"""`scripts/rescore_response.py` with each plan's rows weighing WEIGHT times their effective count in
the fit of its codes (research log entry 88): the plan-alone codes of `calibrate_by_response`; the
joint fit with ordinary use weighs the plan as before (it starts from these codes). Usage, from the
repository root:

    python reports/cross_sensor_response_gpu/entry88/code_weight.py WEIGHT RUN --registry REG \\
        --out OUT [rescore_response.py's options]
"""

import runpy
import sys

import anytip.train.response as response

if len(sys.argv) < 3:
    sys.exit(__doc__)
WEIGHT = float(sys.argv.pop(1))
fitted = response.fit_codes


def weighted(fit, X, Y, n_effective, *rest, **kwargs):
    """`fit_codes` with every job's effective row count times WEIGHT."""
    return fitted(fit, X, Y, [WEIGHT * n for n in n_effective], *rest, **kwargs)


response.fit_codes = weighted  # the name calibrate_by_response calls; label_free holds its own
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
