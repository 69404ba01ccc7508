"""What each uncertainty method costs on the unit: parameters and multiply-accumulates per
inference of the networks and detectors it runs."""

from __future__ import annotations

from typing import Any

import numpy as np

from anytip.models.heteroscedastic import hetero_config
from anytip.models.mlp import MLPConfig
from anytip.uncertainty.rest_drift import TAUS_ROWS, RestDriftDetector


def _macs(config: MLPConfig) -> int:
    return sum(i * o for i, o in zip(config.sizes[:-1], config.sizes[1:], strict=True))


def embedded_costs(sizes: tuple[int, ...]) -> dict[str, Any]:
    """Costs of the point MLP of `sizes`, its heteroscedastic twin and the rest-drift detector:
    {"point": {"params", "macs"}, "hetero": {...}, "rest_drift": {"parameters", "macs", "state"},
    "inputs": C, "outputs": d}."""
    base = MLPConfig(sizes=sizes)
    het = hetero_config(base)
    channels, features = sizes[0], 2 * len(TAUS_ROWS) + 2
    rest = RestDriftDetector(np.zeros((channels, features)), np.zeros(channels), np.eye(channels), 1).cost
    return {"point": {"params": base.n_params, "macs": _macs(base)},
            "hetero": {"params": het.n_params, "macs": _macs(het)},
            "rest_drift": rest, "inputs": channels, "outputs": sizes[-1]}
