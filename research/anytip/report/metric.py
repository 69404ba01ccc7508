"""A target as reports show it: its result key, its short name and its axis label."""

from __future__ import annotations

from typing import NamedTuple


class Metric(NamedTuple):
    """One target of the sensor model as a report column."""

    key: str  # the result rows' key, e.g. force_rmse_n
    name: str  # e.g. force
    label: str  # e.g. force RMSE [N]


FINGERTIP_METRICS = (Metric("force_rmse_n", "force", "force RMSE [N]"),
                     Metric("angle_rmse_rad", "angle", "angle RMSE [rad]"))
