"""Research log entry 192: entry 191's 64 fresh validation units pressed through the designed 30 s plan too
(`plan30`, added to `data/val191d` and `data/val191o`; their full and 120 s runs are simulated again and found
unchanged, as a run of the same seed, unit and protocol is the same run). Entry 195 calls `main` too.

    python reports/cross_sensor_response_gpu/entry192/make_data.py > \\
        reports/cross_sensor_response_gpu/entry192/logs/data.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.sensor.fleet import FleetConfig, load_fleet_config

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "make_data.py"))


def main(protocols: tuple[str, ...] = ("full", "plan120", "plan30"),
         registries: tuple[tuple, ...] = E191["REGISTRIES"]) -> None:
    """Simulate entry 191's units of `registries` again through `protocols`: the last one is added, the runs
    of the others come out unchanged (entry 195 adds plan60 to the other elastomer's)."""
    for _, target, fleet, seed in registries:
        config = FleetConfig() if fleet is None else load_fleet_config(fleet)
        added, unchanged = simulate_into(Registry(target), config, E191["UNITS"], seed=seed,
                                         protocols=protocols)
        print(f"{target}: {added} {protocols[-1]} runs added, {unchanged} runs unchanged")


if __name__ == "__main__":
    main()
