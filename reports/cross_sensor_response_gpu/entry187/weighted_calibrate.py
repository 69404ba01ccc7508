"""Research log entry 187: `anytip calibrate` with the joint fit's weights scaled, nothing else changed. The
use's independent rows (`FleetUse.n_effective`) are multiplied by U and the plan's labeled rows'
(`Labeled.n_eff`, which also weighs the plan's own start fit) by P, inside `unit_codes_with_use` as `anytip
calibrate` calls it.

    python reports/cross_sensor_response_gpu/entry187/weighted_calibrate.py U P \\
        calibrate --model ... --out ...
"""

from __future__ import annotations

import sys
from dataclasses import replace

import anytip.calibrate.response as calibrate_response
from anytip.cli import main
from anytip.train.label_free import Labeled, unit_codes_with_use


def weighted(use: float, plan: float):
    """`unit_codes_with_use` with the use's effective rows times `use` and the plan's times `plan`."""
    def fit(fit, recipe, fleet, X, Y0, candidates, seed, labeled=None, first=None):
        fleet = replace(fleet, effective_hz=fleet.effective_hz * use)
        if labeled is not None:
            labeled = Labeled(labeled.X, labeled.Y, labeled.n_eff * plan)
        return unit_codes_with_use(fit, recipe, fleet, X, Y0, candidates, seed, labeled, first)
    return fit


if __name__ == "__main__":
    calibrate_response.unit_codes_with_use = weighted(float(sys.argv[1]), float(sys.argv[2]))
    main(sys.argv[3:])
