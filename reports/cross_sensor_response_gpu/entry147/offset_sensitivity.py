"""Research log entry 147, read after its runs (exploratory, deciding nothing): does a held-out unit's
sensitivity to a barometer offset say which of its designed plan's intervals fall short? The designed plan is
pressed in the first minutes after the tare, and the test rows span the dome's warm-up (entries 63-64), so a
unit whose outputs move most per pascal of offset would need a wider interval than its plan's residuals show.

Sensitivity, per unit and output (output unit per Pa): the norm over the eight barometers of the least-squares
slopes of the output on the pressures, over the contact rows of the unit's designed runs (`plan150`, which its
plan's presses come from). Printed per output: the Spearman correlation over the 88 held-out units of the
interval's excess, log(needed80 / width), with log(sensitivity / own half-width) and with log(sensitivity);
and the ceiling of widths sqrt(width^2 + (k s)^2), s the sensitivity scaled to the width's median, per k: the
best single factor per output, picked on these held-out units themselves
(`uncertainty.fleet_margin.factor_ceiling`; an optimistic bound, not a method). From the repository root:

    python reports/cross_sensor_response_gpu/entry147/offset_sensitivity.py
"""

from __future__ import annotations

import runpy
import sqlite3
from pathlib import Path

import h5py
import numpy as np
from scipy.stats import spearmanr

from anytip.uncertainty.fleet_margin import factor_ceiling

G = Path("reports/cross_sensor_response_gpu")
REGISTRY = Path("data/fleet88h")
RUNS = [G / f"entry147/at120/fleet88_seed{k}" for k in (0, 1)]
METHODS = ("response@designed", "response+use@designed")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
SCALES = (0.0, 0.1, 0.3, 1.0, 3.0)
rows_by_unit = runpy.run_path(str(G / "entry106/analyse.py"))["rows_by_unit"]


def sensitivity(db: sqlite3.Connection, unit: str) -> np.ndarray:
    """(D,) the norm over barometers of each output's least-squares slope on the pressures (per Pa), over
    the contact rows of the unit's plan150 runs."""
    x, y = [], []
    for (path,) in db.execute("select path from runs where unit = ? and protocol = 'plan150'", (unit,)):
        with h5py.File(REGISTRY / path) as f:
            contact = f["in_contact"][()].astype(bool)
            x.append(f["pressure"][()][contact])
            y.append(np.concatenate([f["force"][()], f["angles"][()]], axis=1)[contact])
    p, t = np.concatenate(x).astype(float), np.concatenate(y).astype(float)
    design = np.c_[p - p.mean(0), np.ones(len(p))]
    slopes = np.linalg.lstsq(design, t, rcond=None)[0][:-1]  # (8, D)
    return np.sqrt((slopes**2).sum(0))


def main() -> None:
    with sqlite3.connect(REGISTRY / "catalog.sqlite") as db:
        for method in METHODS:
            rows = rows_by_unit(RUNS, method)
            units = sorted(rows)

            def field(key: str, units: list[str] = units, rows: dict = rows) -> np.ndarray:
                return np.array([[rows[u][f"{o}_{key}"] for o in OUTPUTS] for u in units])

            own, width = field("halfwidth"), field("fleet_halfwidth")
            n80, n85, n95 = (field(f"needed{q}_halfwidth") for q in (80, 85, 95))
            s = np.array([sensitivity(db, u) for u in units])
            excess = np.log(n80 / width)
            print(f"{method}, {len(units)} held-out units:")
            for d, o in enumerate(OUTPUTS):
                a = spearmanr(excess[:, d], np.log(s[:, d] / own[:, d])).correlation
                b = spearmanr(excess[:, d], np.log(s[:, d])).correlation
                print(f"  {o}: Spearman with log(sensitivity / own) {a:+.2f}, with log(sensitivity) {b:+.2f}")
            scaled = s * np.median(width, 0) / np.median(s, 0)
            for k in SCALES:
                c = factor_ceiling(np.sqrt(width**2 + (k * scaled) ** 2), n80, n85, n95)
                print(f"  k {k:g}: one factor per output puts at most {c.free_in_band:.0%} in the band, "
                      f"{c.safe_in_band:.0%} with none below 0.80")


if __name__ == "__main__":
    main()
