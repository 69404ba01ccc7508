"""Reading training curves: when did a run first reach a given accuracy?"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal


def time_to_target(history: Sequence[dict[str, Any]], target_force_rmse: float | Sequence[float],
                   tol: float = 0.05, key: str = "val_force_rmse",
                   reduce: Literal["mean", "max"] = "mean") -> float | None:
    """Training seconds (`elapsed_s`) at the first row that reaches the target, else None.

    A row reaches a scalar target when its `key` <= target * (1 + tol); a per-unit list
    in the row is first reduced by `reduce` ("max": every unit is there). With one target
    per unit, a row reaches it when every unit u has value[u] <= target[u] * (1 + tol).
    """
    for row in history:
        value = row[key]
        if isinstance(target_force_rmse, Sequence):
            if all(v <= t * (1 + tol) for v, t in zip(value, target_force_rmse, strict=True)):
                return float(row["elapsed_s"])
            continue
        if isinstance(value, list | tuple):
            value = max(value) if reduce == "max" else sum(value) / len(value)
        if value <= target_force_rmse * (1 + tol):
            return float(row["elapsed_s"])
    return None


def select_units(history: Sequence[dict[str, Any]], units: Sequence[int]) -> list[dict[str, Any]]:
    """Fleet history rows with every per-unit list cut down to `units`."""
    return [{k: ([v[u] for u in units] if isinstance(v, list) else v) for k, v in row.items()}
            for row in history]
