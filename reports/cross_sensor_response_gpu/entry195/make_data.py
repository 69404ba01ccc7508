"""Research log entry 195: entry 191's 32 fresh units of the other elastomer pressed through the designed 60 s
plan too (`plan60`, added to `data/val191o`; their other runs are simulated again and found unchanged).

    python reports/cross_sensor_response_gpu/entry195/make_data.py > \\
        reports/cross_sensor_response_gpu/entry195/logs/data.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.sensor.fleet import load_fleet_config

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "make_data.py"))

if __name__ == "__main__":
    _, target, fleet, seed = E191["REGISTRIES"][1]
    added, unchanged = simulate_into(Registry(target), load_fleet_config(fleet), E191["UNITS"], seed=seed,
                                     protocols=("full", "plan120", "plan30", "plan60"))
    print(f"{target}: {added} plan60 runs added, {unchanged} runs unchanged")
