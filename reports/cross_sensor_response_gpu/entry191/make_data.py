"""Research log entry 191: the fresh validation units and their logs. `data/val191d`: a copy of
`data/fleet88p` (payloads linked, catalog copied) with 32 more default fingertips (seed 41, SIM41-000 to
031, the units entry 98 validated on) pressed through the full protocol and the designed 120 s plan;
`data/val191o`: a copy of `data/other16p` with 32 more units of the other elastomer (seed 24, SIM24-000 to
031, entry 98's too). Each new unit's session of ordinary use (entry 177's `use` protocol, its own draw, runs
numbered after 100 as entry 181 numbered them) is written as ordinary-use logs (pressures alone) under
`build/entry191_logs/`.

    python reports/cross_sensor_response_gpu/entry191/make_data.py > \\
        reports/cross_sensor_response_gpu/entry191/logs/data.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.data.simulated import as_run, simulate_into
from anytip.data.use_log import UseLog, write_use_log
from anytip.sensor.fleet import FleetConfig, load_fleet_config
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng

HERE = Path(__file__).parent
linked_copy = runpy.run_path(str(HERE.parent / "entry178" / "make_registries.py"))["linked_copy"]
USE = runpy.run_path(str(HERE.parent / "entry177" / "simulate_use.py"))["USE"]
LOGS, UNITS = Path("build/entry191_logs"), 32
# (source registry, target, fleet config or None for the default fingertip, seed)
REGISTRIES = (("data/fleet88p", "data/val191d", None, 41),
              ("data/other16p", "data/val191o", "configs/fleets/other_elastomer.yaml", 24))


def main(logs: Path = LOGS, registries: tuple = REGISTRIES) -> None:
    """Each of `registries`' (source, target, fleet config or None, seed) made, its units' logs under `logs`
    (entry 201 gives its own)."""
    logs.mkdir(parents=True, exist_ok=True)
    for source, target, fleet, seed in registries:
        reg = linked_copy(Path(source), Path(target))
        config = FleetConfig() if fleet is None else load_fleet_config(fleet)
        added, _ = simulate_into(reg, config, UNITS, seed=seed, protocols=("full", "plan120"))
        written = 0
        for index in range(UNITS):
            params = draw_unit(config, unit_rng(seed, index))
            for run in map(as_run, simulate_unit(params, USE, seed, index, None, config.run, 100)):
                write_use_log(UseLog.of_run(run), logs / f"{run.sensor_id}_o{run.orientation_deg:g}.h5")
                written += 1
        print(f"{target}: {added} runs of {UNITS} units (seed {seed}) added to a copy of {source}; "
              f"{written} sessions written as logs under {logs}")


if __name__ == "__main__":
    main()
