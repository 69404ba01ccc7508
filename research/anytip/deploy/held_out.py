"""Which rows of a unit its model never trained on, so that an export's RMSE is not on training data.

A per-unit model saved by an experiment sits in `RUN/models/<name>_seed<N>/model.safetensors`, beside
the run's `provenance.json` and `config.yaml`; from those:
- cross_sensor: the unit's held-out patch cells, as `provenance.json` records them per seed;
- baseline: the patch cells its `patches` split held out (the first block of models in the file),
  re-drawn from the run's recorded runs, unit order and `splits.patch_test_fraction` exactly as the
  pipeline drew them (`anytip.pipelines.common.patch_test_mask`).
A model folded by `anytip calibrate` records its calibration runs; its other runs are held out when
the unit is not one of the shared model's training units.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from anytip.errors import AnytipError
from anytip.models.io import LoadedModels, model_paths
from anytip.validation import read_yaml


@dataclass
class HeldOut:
    """Rows of one unit that its model never trained on.

    patches: patch cells (None: every cell); runs: the run ids to take rows from (None: all the
    unit's runs); exclude_runs: run ids to leave out; protocols: run protocols to keep (None: all).
    """

    patches: list[int] | None = None
    runs: list[str] | None = None
    exclude_runs: list[str] | None = None
    protocols: list[str] | None = None
    note: str = ""

    def describe(self) -> dict[str, Any]:
        return {"patches": self.patches, "runs": self.runs, "exclude_runs": self.exclude_runs,
                "protocols": self.protocols, "note": self.note}


def parse_spec(spec: str) -> tuple[Path, int | None]:
    """`RUN_DIR[:SEED]` (the `--held-out` option) -> (run directory, seed or None)."""
    m = re.fullmatch(r"(.+?)(?::(\d+))?", spec)
    if m is None or not m.group(1):
        raise AnytipError(f"--held-out {spec!r}: expected RUN_DIR or RUN_DIR:SEED")
    return Path(m.group(1)), None if m.group(2) is None else int(m.group(2))


def _read_json(path: Path) -> dict[str, Any]:
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise AnytipError(f"{path}: cannot read the run's record ({e})") from None


def _pipeline(run_dir: Path) -> str | None:
    try:
        return read_yaml(run_dir / "config.yaml").get("pipeline")
    except AnytipError:
        return None


def from_run(run_dir: str | Path, seed: int | None, unit: str, index: int = 0,
             registry=None) -> HeldOut:
    """The unit's held-out rows in an experiment run directory (cross_sensor or baseline); `index` is
    the unit's model index in the run's per-unit model file (baseline: the split it was trained on)."""
    run_dir = Path(run_dir)
    prov = _read_json(run_dir / "provenance.json")
    if "cross_sensor" in prov:
        return _cross_sensor(run_dir, prov, seed, unit)
    if _pipeline(run_dir) == "baseline":
        return _baseline(run_dir, prov, seed, unit, index, registry)
    raise AnytipError(f"{run_dir}: not a cross_sensor or baseline run (no held-out rows recorded there)")


def _cross_sensor(run_dir: Path, prov: dict[str, Any], seed: int | None, unit: str) -> HeldOut:
    seeds = prov["cross_sensor"]
    key = f"seed{seed}" if seed is not None else (next(iter(seeds)) if len(seeds) == 1 else None)
    if key is None:
        raise AnytipError(f"{run_dir}: the run has seeds {sorted(seeds)}; name one (RUN_DIR:SEED)")
    try:
        patches = seeds[key]["test_patches"][unit]
    except KeyError:
        raise AnytipError(f"{run_dir}/provenance.json: no held-out patches of unit {unit!r} for "
                          f"{key}") from None
    return HeldOut(patches=[int(p) for p in patches],
                   note=f"patches {run_dir} held out for unit {unit} in {key} (cross_sensor)")


def _baseline(run_dir: Path, prov: dict[str, Any], seed: int | None, unit: str, index: int,
              registry) -> HeldOut:
    from anytip.data.arrays import load_arrays
    from anytip.data.splits import patch_test_mask

    units, seeds = list(prov.get("units") or []), list(prov.get("seeds") or [])
    seed = seed if seed is not None else (seeds[0] if len(seeds) == 1 else None)
    if seed is None:
        raise AnytipError(f"{run_dir}: the run has seeds {seeds}; name one (RUN_DIR:SEED)")
    if unit not in units:
        raise AnytipError(f"{run_dir}/provenance.json: unit {unit!r} is not one of the run's units {units}")
    if index >= len(units):
        raise AnytipError(f"{run_dir}: model {index} of unit {unit} is a random-rows model; its held-out "
                          "rows are not whole patches")
    if registry is None:
        raise AnytipError(f"{run_dir}: the baseline's held-out patches are re-drawn from the registry; "
                          "give --registry")
    cfg = read_yaml(run_dir / "config.yaml")
    fraction = float(cfg["splits"]["patch_test_fraction"])
    runs = [r for r in registry.list_runs(unit=unit) if r.run_id in set(prov.get("runs") or [])]
    if not runs:
        raise AnytipError(f"registry {registry.root} holds none of the runs {run_dir} trained unit "
                          f"{unit} on")
    patch = load_arrays(registry, runs).patch
    cells = np.unique(patch[patch_test_mask(fraction, seed)(patch, units.index(unit))])
    return HeldOut(patches=cells.tolist(), runs=[r.run_id for r in runs],
                   note=f"patches {run_dir} held out for unit {unit} in seed {seed} (baseline, "
                        f"patch_test_fraction {fraction}), re-drawn from its recorded runs")


def run_dir_of(model: Path) -> Path | None:
    """RUN for RUN/models/<dir>/model.safetensors when RUN holds a provenance.json."""
    tensors, _ = model_paths(model)
    full = tensors.resolve()
    if full.parent.parent.name != "models" or not (full.parents[2] / "provenance.json").exists():
        return None
    given = tensors.parent.parent.parent  # as given (relative paths stay relative in reports)
    return given if given.resolve() == full.parents[2] else full.parents[2]


def _seed_of(model: Path, loaded: LoadedModels) -> int | None:
    if "seed" in loaded.meta:
        return int(loaded.meta["seed"])
    m = re.search(r"seed(\d+)", model_paths(model)[0].parent.name)
    return int(m.group(1)) if m else None


def _folded(loaded: LoadedModels, unit: str) -> HeldOut | None:
    """A model folded by `anytip calibrate`: the unit's runs other than its calibration runs, when the
    unit is not one of the shared model's training units."""
    meta = loaded.meta
    if "calibration_runs" not in meta or "shared_model" not in meta:
        return None
    shared_json = model_paths(meta["shared_model"])[1]
    try:
        trained = json.loads(shared_json.read_text())["meta"]["unit_ids"]
    except (OSError, ValueError, KeyError):
        return None
    if unit in trained:
        return None
    return HeldOut(exclude_runs=list(meta["calibration_runs"]),
                   note=f"the unit's runs other than the {len(meta['calibration_runs'])} runs `anytip "
                        f"calibrate` used; unit {unit} is not a training unit of {meta['shared_model']}")


def for_model(model: str | Path, loaded: LoadedModels, index: int, unit: str,
              registry=None) -> tuple[HeldOut | None, str]:
    """(the held-out rows a model file's location or metadata tell, or None; why not, if None)."""
    model = Path(model)
    folded = _folded(loaded, unit)
    if folded is not None:
        return folded, ""
    run_dir = run_dir_of(model)
    if run_dir is None:
        return None, (f"{model} is not in an experiment run's models/ directory and records no "
                      "calibration runs")
    try:
        return from_run(run_dir, _seed_of(model, loaded), unit, index, registry), ""
    except AnytipError as e:
        return None, str(e)
