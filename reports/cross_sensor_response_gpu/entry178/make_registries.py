"""Research log entry 178: the calibration registries. `data/use178`: a copy of `data/fleet88g` (payloads
linked, catalog copied) in which each of UNITS keeps its designed plan (`plan120`) and gains a session of
ordinary use, entry 177's `use` protocol simulated for the same unit (seed 40, its runs numbered after its 17
in fleet88g); its full, short and quick runs are left out, so its calibration stream is that session.
`data/use178det`: the same with each session's `in_contact` replaced by entry 176's `tracking` detector at
200 Pa, so its presses are what a detector on pressures finds.

    python reports/cross_sensor_response_gpu/entry178/make_registries.py \
        data/fleet88g data/use178 data/use178det
"""

from __future__ import annotations

import dataclasses
import runpy
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry
from anytip.data.simulated import as_run
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng

HERE = Path(__file__).parent
USE = runpy.run_path(str(HERE.parent / "entry177" / "simulate_use.py"))["USE"]
DETECT = runpy.run_path(str(HERE.parent / "entry176" / "contact_from_pressure.py"))
# fleet88 fold 0's first 16 held-out units (entry 147's run)
UNITS = [f"SIM40-{i:03d}" for i in (1, 2, 4, 5, 6, 11, 14, 15, 20, 22, 23, 24, 25, 27, 32, 33)]
SEED, RUNS_BEFORE, THRESHOLD_PA = 40, 17, 200.0


def linked_copy(source: Path, target: Path) -> Registry:
    """A registry at `target` sharing `source`'s payload files (hard links) with a catalog of its own."""
    if target.exists():
        raise SystemExit(f"{target} exists")
    subprocess.run(["cp", "-al", str(source), str(target)], check=True)
    catalog = target / "catalog.sqlite"
    catalog.unlink()
    shutil.copy2(source / "catalog.sqlite", catalog)
    return Registry(target)


def tracked_contact(run) -> np.ndarray:  # noqa: ANN001 - a CalibrationRun
    """(n,) bool: entry 176's `tracking` detector at THRESHOLD_PA on the run's pressures alone."""
    t, p = run.time, run.pressure.astype(np.float64)
    rest = p[t - t[0] < DETECT["REST_S"]].mean(0)
    fixed = (np.abs(p - rest) > THRESHOLD_PA).any(1)
    base = DETECT["tracking_baseline"](t, p, ~fixed)
    return (np.abs(p - base) > THRESHOLD_PA).any(1)


def main(source: str, flagged: str, detected: str) -> None:
    reg = linked_copy(Path(source), Path(flagged))
    config = FleetConfig()
    for unit in UNITS:
        for record in reg.list_runs(unit=unit):
            if record.protocol in ("full", "short", "quick"):
                reg.remove(record.run_id)
        index = int(unit.split("-")[1])
        params = draw_unit(config, unit_rng(SEED, index))
        session = simulate_unit(params, USE, SEED, index, None, config.run, RUNS_BEFORE)
        reg.add_runs([as_run(r) for r in session])
    det = linked_copy(Path(flagged), Path(detected))
    shares = []
    for unit in UNITS:
        for record in det.list_runs(unit=unit):
            if record.protocol != "use":
                continue
            run = det.open_run(record.run_id)
            found = tracked_contact(run)
            shares.append((np.count_nonzero(found & ~run.in_contact), np.count_nonzero(found)))
            det.remove(record.run_id)
            det.add_runs([dataclasses.replace(run, in_contact=found)])
    outside, found = np.sum(shares, 0)
    print(f"{len(UNITS)} units; {len(shares)} use runs; the detector's rows outside the force flag: "
          f"{outside / found:.3f} of {found}")


if __name__ == "__main__":
    main(*sys.argv[1:4])
