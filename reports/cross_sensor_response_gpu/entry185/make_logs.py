"""Research log entry 185: two more sessions of ordinary use for each of entry 178's units (entry 177's `use`
protocol, the unit's own draw, the run numbers after entry 178's session), written as ordinary-use logs under
build/entry185_logs/ (UNIT_s2_*.h5, UNIT_s3_*.h5), with each log's contact seconds as `--use-log` finds them.

    python reports/cross_sensor_response_gpu/entry185/make_logs.py > \\
        reports/cross_sensor_response_gpu/entry185/logs/logs.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.data.simulated import as_run
from anytip.data.use_log import UseLog, use_rows, write_use_log
from anytip.sensor.fleet import FleetConfig, RunConditions
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng
from anytip.sensor.variation import UnitParams

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "make_registries.py"))
OUT = Path("build/entry185_logs")


def more_sessions(params: UnitParams, conditions: RunConditions, unit: tuple[int, int, str], first: int,
                  out: Path) -> list[float]:
    """Sessions 2 and 3 of entry 177's `use` protocol for a unit (`unit`: the fleet's seed, the unit's index
    and name; `params`, under `conditions`), their runs numbered from `first` (after session 1's three),
    written as ordinary-use logs NAME_s2_*.h5 and NAME_s3_*.h5 under `out`; each log's contact seconds as
    `--use-log` finds them."""
    seed, index, name = unit
    held = []
    for session in (2, 3):
        runs = simulate_unit(params, E178["USE"], seed, index, None, conditions, first + 3 * (session - 2))
        for run in map(as_run, runs):
            log = UseLog.of_run(run)
            write_use_log(log, out / f"{name}_s{session}_o{run.orientation_deg:g}.h5")
            held.append(use_rows(log, 1e9)[1])
    return held


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    config = FleetConfig()
    for unit in E178["UNITS"]:
        index = int(unit.split("-")[1])
        params = draw_unit(config, unit_rng(E178["SEED"], index))
        held = more_sessions(params, config.run, (E178["SEED"], index, unit), E178["RUNS_BEFORE"] + 3, OUT)
        print(f"{unit}: sessions 2-3, {len(held)} logs, {sum(held):.1f} contact-s found")


if __name__ == "__main__":
    main()
