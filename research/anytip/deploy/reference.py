"""Reference rows an export is verified on: a unit's registry rows, or synthetic pressures."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from anytip.deploy.net import DeployNet


@dataclass
class Reference:
    """x (B, 8) tared Pa; targets (B, 5) N, rad or None; cal: row mask used to calibrate int8."""

    x: np.ndarray
    targets: np.ndarray | None
    cal: np.ndarray
    source: str
    note: str
    runs: list[str] = field(default_factory=list)

    @property
    def eval_rows(self) -> np.ndarray:
        return ~self.cal

    def describe(self) -> dict:
        return {"source": self.source, "note": self.note, "rows": int(len(self.x)),
                "calibration_rows": int(self.cal.sum()), "runs": self.runs}


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
                       patches: list[int] | None = None,
                       protocols: list[str] | None = None) -> Reference | None:
    """Up to `rows` rows of the unit's runs, in contact (|F| > 0.5 N); half calibrate int8 rounding,
    the other half are scored. `protocols` keeps runs of those protocols; `patches` keeps rows of
    those patch cells (a held-out unit's test patches: rows no model trained on). None when the
    registry has no run of the unit."""
    from anytip.data.arrays import CONTACT_FORCE_N, load_arrays

    runs = registry.list_runs(unit=unit)
    if protocols is not None:
        runs = [r for r in runs if r.protocol in protocols]
    if not runs:
        return None
    arr = load_arrays(registry, runs)
    keep = np.linalg.norm(arr.force, axis=1) > CONTACT_FORCE_N
    if patches is not None:
        keep &= np.isin(arr.patch, patches)
        if not keep.any():
            return None
    idx = np.flatnonzero(keep)
    rng = np.random.default_rng(seed)
    idx = np.sort(rng.choice(idx, size=min(rows, len(idx)), replace=False))
    cal = np.zeros(len(idx), bool)
    cal[rng.permutation(len(idx))[: len(idx) // 2]] = True
    which = (f"its held-out patches {list(patches)}" if patches is not None
             else "all its rows, so they may include rows the model was trained on")
    return Reference(arr.pressure[idx].astype(np.float64), arr.targets[idx].astype(np.float64), cal,
                     "registry" if patches is None else "registry, held-out patches",
                     f"{len(idx)} in-contact rows of unit {unit}'s runs "
                     f"{sorted({r.protocol for r in runs}, key=str)} ({which}); half calibrate the int8 "
                     "rounding, the other half are scored", [r.run_id for r in runs])
