"""Reference rows an export is verified on: a unit's registry rows, or synthetic pressures."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from anytip.data.runfile import V1_LAYOUT, TargetLayout
from anytip.deploy.held_out import HeldOut
from anytip.deploy.net import DeployNet

TRAINING_ROWS_WARNING = ("nothing tells which of the unit's rows the model trained on: the RMSE figures "
                         "may include training rows (give --held-out RUN_DIR[:SEED])")


@dataclass
class Reference:
    """x (B, C) tared Pa; targets (B, D) in the units of `layout` (the fingertip's: N, rad) or None;
    cal: row mask used to calibrate int8."""

    x: np.ndarray
    targets: np.ndarray | None
    cal: np.ndarray
    source: str
    note: str
    runs: list[str] = field(default_factory=list)
    held_out: HeldOut | None = None  # the rule that chose held-out rows (None: all the unit's rows)
    layout: dict[str, TargetLayout] = field(default_factory=lambda: dict(V1_LAYOUT))  # the targets' columns

    @property
    def may_include_training_rows(self) -> bool:
        """True when scored rows have targets but nothing says the model never trained on them."""
        return self.targets is not None and self.held_out is None

    @property
    def eval_rows(self) -> np.ndarray:
        return ~self.cal

    def describe(self) -> dict:
        out = {"source": self.source, "note": self.note, "rows": int(len(self.x)),
               "calibration_rows": int(self.cal.sum()), "runs": self.runs,
               "held_out": None if self.held_out is None else self.held_out.describe(),
               "rmse_may_include_training_rows": self.may_include_training_rows}
        return out | ({"warning": TRAINING_ROWS_WARNING} if self.may_include_training_rows else {})


def synthetic_reference(net: DeployNet, rows: int = 4000, seed: int = 0) -> Reference:
    """mean + std * N(0, 1) from the model's own input scaler; no targets."""
    rng = np.random.default_rng(seed)
    x = net.in_mean + net.in_std * rng.standard_normal((rows, net.n_inputs))
    cal = np.zeros(rows, bool)
    cal[: rows // 2] = True
    return Reference(x, None, cal, "synthetic",
                     "no registry rows for this unit: inputs drawn from the model's input scaler "
                     "(mean + std * N(0, 1)); errors are against the model, not against targets")


def registry_reference(registry, unit: str, rows: int = 20000, seed: int = 0,
                       held_out: HeldOut | None = None) -> Reference | None:
    """Up to `rows` label rows of the unit's runs (with a force target: |F| > 0.5 N); half calibrate
    int8 rounding,
    the other half are scored. `held_out` keeps the rows its model never trained on (runs,
    protocols, patch cells); without it every row of the unit counts and the reference says that
    they may include training rows. None when no row is left."""
    from anytip.data.arrays import CONTACT_FORCE_N, load_arrays

    h = held_out or HeldOut()
    runs = [r for r in registry.list_runs(unit=unit)
            if (h.protocols is None or r.protocol in h.protocols) and (h.runs is None or r.run_id in h.runs)
            and r.run_id not in (h.exclude_runs or [])]
    if not runs:
        return None
    arr = load_arrays(registry, runs)
    keep = np.ones(arr.n_rows, bool)  # label rows: in contact
    if arr.layout.get("force") == V1_LAYOUT["force"]:
        keep = np.linalg.norm(arr.force, axis=1) > CONTACT_FORCE_N
    if h.patches is not None:
        keep &= np.isin(arr.patch, h.patches)
    if not keep.any():
        return None
    idx = np.flatnonzero(keep)
    rng = np.random.default_rng(seed)
    idx = np.sort(rng.choice(idx, size=min(rows, len(idx)), replace=False))
    cal = np.zeros(len(idx), bool)
    cal[rng.permutation(len(idx))[: len(idx) // 2]] = True
    which = (f"held out: {held_out.note}" if held_out is not None
             else "all its rows, so they may include rows the model was trained on")
    return Reference(arr.pressure[idx].astype(np.float64), arr.targets[idx].astype(np.float64), cal,
                     "registry" if held_out is None else "registry, held out",
                     f"{len(idx)} in-contact rows of unit {unit}'s runs "
                     f"{sorted({r.protocol for r in runs}, key=str)} ({which}); half calibrate the int8 "
                     "rounding, the other half are scored", [r.run_id for r in runs], held_out, arr.layout)
