"""Reading training curves: when did a run first reach a given accuracy?"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal


def time_to_target(history: Sequence[dict[str, Any]], target_force_rmse: float, tol: float = 0.05,
                   key: str = "val_force_rmse", reduce: Literal["mean", "max"] = "mean"
                   ) -> float | None:
    """Training seconds (`elapsed_s`) at the first row whose `key` <= target * (1 + tol).

    A row's value may be one number or a per-unit list, reduced by `reduce` ("max": every
    unit has reached the target). None if the run never got there.
    """
    threshold = target_force_rmse * (1 + tol)
    for row in history:
        value = row[key]
        if isinstance(value, list | tuple):
            value = max(value) if reduce == "max" else sum(value) / len(value)
        if value <= threshold:
            return float(row["elapsed_s"])
    return None
