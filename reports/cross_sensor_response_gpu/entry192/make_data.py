"""Research log entry 192: entry 191's 64 fresh validation units pressed through the designed 30 s plan too
(`plan30`, added to `data/val191d` and `data/val191o`; their full and 120 s runs are simulated again and found
unchanged, as a run of the same seed, unit and protocol is the same run).

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


def main() -> None:
    for _, target, fleet, seed in E191["REGISTRIES"]:
        config = FleetConfig() if fleet is None else load_fleet_config(fleet)
        added, unchanged = simulate_into(Registry(target), config, E191["UNITS"], seed=seed,
                                         protocols=("full", "plan120", "plan30"))
        print(f"{target}: {added} plan30 runs added, {unchanged} runs unchanged")


if __name__ == "__main__":
    main()
