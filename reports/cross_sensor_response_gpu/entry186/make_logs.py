"""Research log entry 186: two more sessions of ordinary use for each of other16's units (entry 177's `use`
protocol, the other elastomer's fleet, seed 23, the run numbers after entry 181's session), written as
ordinary-use logs under build/entry186_logs/ (UNIT_s2_*.h5, UNIT_s3_*.h5), with each unit's contact seconds as
`--use-log` finds them.

    python reports/cross_sensor_response_gpu/entry186/make_logs.py > \\
        reports/cross_sensor_response_gpu/entry186/logs/logs.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.sensor.fleet import load_fleet_config
from anytip.sensor.simulate import draw_unit, unit_rng

HERE = Path(__file__).parent
E181 = runpy.run_path(str(HERE.parent / "entry181" / "make_logs.py"))
E185 = runpy.run_path(str(HERE.parent / "entry185" / "make_logs.py"))
OUT, FIRST_RUN = Path("build/entry186_logs"), 100  # entry 181's session: runs 100-102


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    config = load_fleet_config(E181["FLEET"])
    for index in range(E181["UNITS"]):
        params = draw_unit(config, unit_rng(E181["SEED"], index))
        unit = f"SIM{E181['SEED']}-{index:03d}"
        held = E185["more_sessions"](params, config.run, (E181["SEED"], index, unit), FIRST_RUN + 3, OUT)
        print(f"{unit}: sessions 2-3, {len(held)} logs, {sum(held):.1f} contact-s found")


if __name__ == "__main__":
    main()
