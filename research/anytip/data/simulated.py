"""Fill a registry from the fleet simulator, one unit (all of its runs) per transaction."""

from __future__ import annotations

from collections.abc import Sequence
from itertools import groupby

from rich.progress import track

from anytip.data.registry import Registry
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.simulate import simulate_fleet


def simulate_into(registry: Registry, config: FleetConfig, n_units: int, seed: int,
                  protocols: Sequence[str] = ("full", "short"), progress: bool = False
                  ) -> tuple[int, int]:
    """Simulate `n_units` units and add their runs; returns (runs added, runs already there).

    Re-running with the same arguments adds nothing: simulated runs are deterministic.
    """
    before = {r.run_id for r in registry.list_runs()}
    runs = simulate_fleet(config, n_units=n_units, seed=seed, protocols=tuple(protocols))
    added = unchanged = 0
    for _, unit_runs in track(groupby(runs, key=lambda r: r.sensor_id), total=n_units,
                              description="simulating units", disable=not progress):
        records = registry.add_runs(list(unit_runs))
        new = sum(r.run_id not in before for r in records)
        added, unchanged = added + new, unchanged + len(records) - new
    return added, unchanged
