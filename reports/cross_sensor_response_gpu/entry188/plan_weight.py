"""Research log entry 188: `anytip calibrate` with the plan's independent rows times P where
`calibrate_by_response` fits the unit's codes from them (the code fit and the code draws' covariance), nothing
else changed.

    python reports/cross_sensor_response_gpu/entry188/plan_weight.py P \\
        calibrate --model ... --out ...
"""

from __future__ import annotations

import sys

import anytip.calibrate.response as calibrate_response
from anytip.cli import main
from anytip.train.response import calibrate_by_response


def weighted(plan: float):
    """`calibrate_by_response` with every job's effective rows times `plan`."""
    def fit(fit, source, X, Y, n_effective, *args, **kwargs):
        return calibrate_by_response(fit, source, X, Y, [n * plan for n in n_effective], *args, **kwargs)
    return fit


if __name__ == "__main__":
    calibrate_response.calibrate_by_response = weighted(float(sys.argv[1]))
    main(sys.argv[2:])
