"""Research log entry 181, after its rule: arm B, the same sessions read through the simulator's force flag
instead of the detector, to separate the detector from the session. Each session is simulated again (as
make_logs.py does, bit for bit) and `--use-log`'s rows come from its flag (`use_rows` patched for this
process only); everything else is `anytip calibrate` as run.sh calls it. Into build/entry181/B/.

    python reports/cross_sensor_response_gpu/entry181/flag_arm.py CORE FOLD... > \
        reports/cross_sensor_response_gpu/entry181/logs/flag_CORE.log
"""

from __future__ import annotations

import hashlib
import os
import runpy
import sys
from pathlib import Path

import numpy as np

import anytip.calibrate.response as response
from anytip.calibrate import calibrate_unit
from anytip.data.registry import Registry
from anytip.data.simulated import as_run
from anytip.data.use_log import UseLog
from anytip.sensor.fleet import load_fleet_config
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng

HERE = Path(__file__).parent
MAKE = runpy.run_path(str(HERE / "make_logs.py"))
RUNS = HERE.parent / "entry146" / "at120" / "other16_severe_d0"
HELD_OUT = ((0, 2, 13, 14), (4, 8, 11, 12), (1, 3, 6, 7), (5, 9, 10, 15))  # each fold's units (run.sh)
FOLDS = [[f"SIM23-{i:03d}" for i in fold] for fold in HELD_OUT]
FLAGS: dict[str, np.ndarray] = {}


def flagged_rows(log: UseLog, seconds: float) -> tuple[np.ndarray, float]:
    """`use_rows` with the session's force flag in place of the detector."""
    contact = FLAGS[log.created]
    first = int(np.argmax(contact))
    rows = np.flatnonzero(contact)[: max(1, int(np.floor(seconds * log.sample_rate_hz)))]
    tared = (log.pressure[rows].astype(np.float64) - log.pressure[:first].astype(np.float64).mean(0))
    return tared.astype(np.float32), len(rows) / log.sample_rate_hz


def main(core: int, folds: list[int]) -> None:
    os.sched_setaffinity(0, {core})
    config = load_fleet_config(MAKE["FLEET"])
    response.use_rows = flagged_rows
    registry = Registry("data/other16")
    for fold in folds:
        for unit in FOLDS[fold]:
            index = int(unit.split("-")[1])
            params = draw_unit(config, unit_rng(MAKE["SEED"], index))
            session = simulate_unit(params, MAKE["USE"], MAKE["SEED"], index, None, config.run, 100)
            runs = [as_run(r) for r in session]
            FLAGS.update({r.created: r.in_contact.astype(bool) for r in runs})
            logs = sorted(Path("build/entry181_logs").glob(f"{unit}_o*.h5"))
            out = Path("build/entry181/B") / unit
            calibrate_unit(RUNS / f"other16_seed{fold}", unit, registry, out, budget_seconds=120,
                           method="response", use_seconds=600, plan_strategy="cover_informative",
                           use_logs=logs)
            digest = hashlib.sha256((out / "model.safetensors").read_bytes()).hexdigest()[:16]
            print(f"B {unit} {digest}", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]), [int(f) for f in sys.argv[2:]])
