"""Research log entry 182: the calibration registry and logs. `data/use182`: a copy of `data/fleet88p`
(payloads linked, catalog copied) in which each of entry 178's UNITS keeps its designs (`plan120`, `plan60`,
`plan30`) and gains entry 178's session of ordinary use (entry 177's `use` protocol, the same seed, index and
run numbers); its full, short and quick runs are left out. Each session is also written as ordinary-use logs
(pressures alone) under `build/entry182_logs/`, as entry 180 wrote them.

    python reports/cross_sensor_response_gpu/entry182/make_registry.py data/fleet88p data/use182
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

from anytip.data.simulated import as_run
from anytip.data.use_log import UseLog, write_use_log
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "make_registries.py"))
LOGS = Path("build/entry182_logs")


def main(source: str, target: str, units: list[str] = E178["UNITS"], logs: Path = LOGS) -> None:
    """`target` from `source` for `units` (entry 178's by default; entry 190 gives fleet88 fold 0's validation
    units), their sessions written as logs under `logs`."""
    reg = E178["linked_copy"](Path(source), Path(target))
    config = FleetConfig()
    for unit in units:
        for record in reg.list_runs(unit=unit):
            if record.protocol in ("full", "short", "quick"):
                reg.remove(record.run_id)
        index = int(unit.split("-")[1])
        params = draw_unit(config, unit_rng(E178["SEED"], index))
        session = simulate_unit(params, E178["USE"], E178["SEED"], index, None, config.run,
                                E178["RUNS_BEFORE"])
        reg.add_runs([as_run(r) for r in session])
    logs.mkdir(parents=True, exist_ok=True)
    written = 0
    for record in reg.list_runs():
        if record.protocol == "use":
            write_use_log(UseLog.of_run(reg.open_run(record.run_id)), logs / f"{record.run_id}.h5")
            written += 1
    print(f"{len(units)} units; {written} use runs written as logs under {logs}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
