"""The baseline pipeline end to end on a tiny fleet: outputs, no leakage, determinism."""

import json
import os
from pathlib import Path

import numpy as np
import torch

from anytip.data.arrays import load_arrays
from anytip.data.splits import patch_test_mask
from anytip.models.io import load_models
from anytip.pipelines.common import per_unit_split
from anytip.runner import run_experiment

REPO = Path(__file__).resolve().parents[1]
FAST_TINY = ["data.protocol=short", "training.epochs=2", "training.batch_size=64"]


def _rowset(x: np.ndarray) -> set[bytes]:
    return {r.tobytes() for r in np.ascontiguousarray(x)}


def test_held_out_patch_rows_never_reach_training(small_registry):
    arrays = load_arrays(small_registry, small_registry.list_runs())
    split = per_unit_split(arrays, arrays.units, patch_test_mask(0.25, seed=0), 0.1, 0, torch.device("cpu"))
    for u, unit in enumerate(arrays.units):
        member = split.data.unit(u)
        seen = _rowset(member.X_train.numpy()) | _rowset(member.X_val.numpy())
        assert not seen & _rowset(split.X_test[u]), unit
        rows = split.test_rows[u]
        own = np.flatnonzero(arrays.unit == u)
        train_patches = set(arrays.patch[np.setdiff1d(own, rows)])
        assert train_patches.isdisjoint(arrays.patch[rows])


def test_baseline_run_writes_contract_and_is_deterministic(small_registry, tmp_path):
    spec = REPO / "experiments" / "baseline.yaml"
    a = run_experiment(spec, small_registry, out=tmp_path / "a", overrides=FAST_TINY, progress=False)
    b = run_experiment(spec, small_registry, out=tmp_path / "b", overrides=FAST_TINY, progress=False)
    ma, mb = (json.loads((d / "metrics.json").read_text()) for d in (a, b))
    assert ma["results"] == mb["results"]
    rows = ma["results"]
    assert len(rows) == 2 * 8 and {r["split"] for r in rows} == {"patches", "random"}
    for r in rows:
        assert r["method"] == "per_unit" and np.isfinite(r["force_rmse_n"]) and r["calib_samples"] > 0
    for name in ("config.yaml", "provenance.json", "report.md", "parity_patches.png", "region_force.png",
                 "force_vs_fz.png", "training_curves.png"):
        assert (a / name).is_file(), name
    prov = json.loads((a / "provenance.json").read_text())
    assert prov["registry_content_hash"] == small_registry.content_hash()
    assert prov["seeds"] == [0] and len(prov["units"]) == 8
    # peak resident memory in GB: torch alone takes a few hundred MB, and no process exceeds the machine
    physical_gb = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 1e9
    assert 0.05 < prov["peak_memory_gb"] < physical_gb
    models = load_models(a / "models" / "per_unit_seed0")
    assert models.model.n_models == 16
    report = (a / "report.md").read_text()
    for split in ("patches", "random"):  # the report's mean row is computed from the metrics rows
        mean = np.mean([r["force_rmse_n"] for r in rows if r["split"] == split])
        assert f"{mean:.4g}" in report or f"{mean:.3f}" in report, (split, mean)
    unit = rows[0]["unit"]
    line = next(x for x in report.splitlines() if x.startswith(f"| {unit} |"))
    assert f"{rows[0]['fx_rmse']:.4g}"[:5] in line


def test_scalers_fit_on_training_rows_only(small_registry, tmp_path):
    spec = REPO / "experiments" / "baseline.yaml"
    out = run_experiment(spec, small_registry, out=tmp_path / "a", overrides=FAST_TINY, progress=False)
    models = load_models(out / "models" / "per_unit_seed0")
    arrays = load_arrays(small_registry, small_registry.list_runs())
    split = per_unit_split(arrays, arrays.units, patch_test_mask(0.2, seed=0), 0.1, 0, torch.device("cpu"))
    for u in range(8):
        train = split.data.unit(u).X_train.double()
        np.testing.assert_allclose(models.in_scaler.mean[u, 0].double(), train.mean(0), rtol=1e-4, atol=1e-2)


def test_baseline_runs_on_a_registry_of_imported_interchange_files(small_registry, tmp_path):
    """Files written by export (any program following CALIBRATION_FORMAT.md) make a registry
    the spec has never seen; the same rows give the same metrics."""
    from anytip.data.registry import Registry

    files = tmp_path / "files"
    for unit in sorted({r.unit for r in small_registry.list_runs()}):
        small_registry.export(unit, files)
    fresh = Registry(tmp_path / "imported")
    report = fresh.import_paths(files)
    assert len(report.added) == len(small_registry.list_runs())
    spec = REPO / "experiments" / "baseline.yaml"
    a = run_experiment(spec, small_registry, out=tmp_path / "a", overrides=FAST_TINY, progress=False)
    b = run_experiment(spec, fresh, out=tmp_path / "b", overrides=FAST_TINY, progress=False)
    ma, mb = (json.loads((d / "metrics.json").read_text())["results"] for d in (a, b))
    assert ma == mb
