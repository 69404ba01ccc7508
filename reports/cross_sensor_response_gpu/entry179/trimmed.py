"""Research log entry 179: a detector on pressures that lets the dome's recovery go, its fraction chosen on
tuning units, and the registry of entry 178's units read through it.

`trimmed_contact`: entry 176's `tracking` detector at 200 Pa, a row kept only where its largest deviation from
the tracked baseline is at least `f` of the largest over the preceding WINDOW_S seconds.

    python reports/cross_sensor_response_gpu/entry179/trimmed.py tune > \
        reports/cross_sensor_response_gpu/entry179/logs/tune.log
    python reports/cross_sensor_response_gpu/entry179/trimmed.py build F data/use178 data/use179det
"""

from __future__ import annotations

import dataclasses
import runpy
import sys
from pathlib import Path

import numpy as np

from anytip.data.contact import ContactDetector
from anytip.data.simulated import as_run
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.simulate import draw_unit, simulate_unit, unit_rng

HERE = Path(__file__).parent
E176 = runpy.run_path(str(HERE.parent / "entry176" / "contact_from_pressure.py"))
E178 = runpy.run_path(str(HERE.parent / "entry178" / "make_registries.py"))
USE = runpy.run_path(str(HERE.parent / "entry177" / "simulate_use.py"))["USE"]
TUNING = [f"SIM40-{i:03d}" for i in (36, 39, 41, 42, 46, 47, 50, 51)]  # fold 0's held-out units 17-24
FRACTIONS, WINDOW_S, THRESHOLD_PA, FIRM_KEPT = (0.05, 0.1, 0.2, 0.3), 2.0, 200.0, 0.99


def trimmed_contact(run, f: float) -> np.ndarray:  # noqa: ANN001 - a CalibrationRun
    """(n,) bool: the detector at fraction f (`anytip.data.contact.ContactDetector`, which holds this entry's
    detector since: rows over 200 Pa from the tracked baseline and at least f of the preceding 2 s's peak)."""
    detector = ContactDetector(threshold_pa=THRESHOLD_PA, fraction=f, window_s=WINDOW_S)
    return detector.contact(run.time, run.pressure, run.sample_rate_hz)


def sessions(units: list[str]) -> list:
    """Each unit's `use` session (fleet88's units, seed 40, numbered as entry 178's), simulated in memory."""
    config, runs = FleetConfig(), []
    for unit in units:
        index = int(unit.split("-")[1])
        params = draw_unit(config, unit_rng(E178["SEED"], index))
        session = simulate_unit(params, USE, E178["SEED"], index, None, config.run, E178["RUNS_BEFORE"])
        runs += [as_run(r) for r in session]
    return runs


def tune() -> None:
    """Per fraction over the tuning units' sessions: firm rows kept, share outside the flag, segments per
    press; and the fraction chosen by the entry's rule."""
    runs = sessions(TUNING)
    print(f"{len(runs)} use sessions of {len(TUNING)} tuning units ({', '.join(TUNING)})\n")
    print("| f | rows at abs(F) >= 1 N kept | found rows outside the flag | segments per press |")
    print("|---|---|---|---|")
    rows = {}
    for f in FRACTIONS:
        counts = np.zeros(7)
        for run in runs:
            firm = np.linalg.norm(run.force, axis=1) >= E176["FIRM_N"]
            counts += E176["score"](trimmed_contact(run, f), run.in_contact.astype(bool), firm)
        rows[f] = (counts[2] / counts[3], (counts[4] - counts[0]) / counts[4], counts[5] / counts[6])
        print(f"| {f:g} | {rows[f][0]:.4f} | {rows[f][1]:.4f} | {rows[f][2]:.3f} |")
    allowed = [f for f in FRACTIONS if rows[f][0] >= FIRM_KEPT]
    chosen = min(allowed, key=lambda f: rows[f][1]) if allowed else None
    print(f"\nchosen: f = {chosen}" if chosen is not None else "\nno fraction keeps 99% of the firm rows")


def build(f: float, source: str, target: str) -> None:
    """`target`: a linked copy of `source` with entry 178's units' `use` runs read through the detector."""
    det = E178["linked_copy"](Path(source), Path(target))
    outside = found = 0
    for unit in E178["UNITS"]:
        for record in det.list_runs(unit=unit):
            if record.protocol != "use":
                continue
            run = det.open_run(record.run_id)
            mask = trimmed_contact(run, f)
            outside += np.count_nonzero(mask & ~run.in_contact)
            found += np.count_nonzero(mask)
            det.remove(record.run_id)
            det.add_runs([dataclasses.replace(run, in_contact=mask)])
    print(f"f = {f:g}: {outside / found:.3f} of {found} found rows outside the force flag")


if __name__ == "__main__":
    tune() if sys.argv[1] == "tune" else build(float(sys.argv[2]), sys.argv[3], sys.argv[4])
