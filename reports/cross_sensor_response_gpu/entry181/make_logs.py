"""Research log entry 181: other16's units' sessions of ordinary use (entry 177's `use` protocol, the other
elastomer's fleet, seed 23), written as ordinary-use logs under build/entry181_logs/, and the contact detector
(`anytip.data.contact`) scored against the sessions' force flag as entry 179 scored it.

    python reports/cross_sensor_response_gpu/entry181/make_logs.py > \
        reports/cross_sensor_response_gpu/entry181/logs/logs.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.data.contact import ContactDetector
from anytip.data.simulated import as_run
from anytip.data.use_log import UseLog, write_use_log
from anytip.sensor.fleet import load_fleet_config
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng

HERE = Path(__file__).parent
E176 = runpy.run_path(str(HERE.parent / "entry176" / "contact_from_pressure.py"))
USE = runpy.run_path(str(HERE.parent / "entry177" / "simulate_use.py"))["USE"]
FLEET, SEED, UNITS, OUT = "configs/fleets/other_elastomer.yaml", 23, 16, Path("build/entry181_logs")


def main() -> None:
    config = load_fleet_config(FLEET)
    OUT.mkdir(parents=True, exist_ok=True)
    counts = np.zeros(7)
    for index in range(UNITS):
        params = draw_unit(config, unit_rng(SEED, index))
        for run in map(as_run, simulate_unit(params, USE, SEED, index, None, config.run, 100)):
            write_use_log(UseLog.of_run(run), OUT / f"{run.sensor_id}_o{run.orientation_deg:g}.h5")
            found = ContactDetector().contact(run.time, run.pressure, run.sample_rate_hz)
            firm = np.linalg.norm(run.force, axis=1) >= E176["FIRM_N"]
            counts += E176["score"](found, run.in_contact.astype(bool), firm)
    print(f"{UNITS} units' sessions ({FLEET}, seed {SEED}) written to {OUT}")
    print(f"rows at abs(F) >= 1 N kept {counts[2] / counts[3]:.4f}; found rows outside the flag "
          f"{(counts[4] - counts[0]) / counts[4]:.4f}; segments per press {counts[5] / counts[6]:.3f}")


if __name__ == "__main__":
    main()
