"""Export RMSE on rows the model never trained on: held-out rows found from the model's run
directory or metadata, or named with --held-out; without them the report says so."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import torch

from anytip.cli import main
from anytip.data.arrays import CONTACT_FORCE_N, load_arrays
from anytip.data.splits import patch_test_mask
from anytip.deploy.export import prepare
from anytip.deploy.held_out import for_model, from_run, parse_spec
from anytip.errors import AnytipError
from anytip.models.io import load_models
from anytip.pipelines.common import per_unit_split
from anytip.runner import run_experiment
from test_deploy_helpers import save_baseline

REPO = Path(__file__).resolve().parents[1]
FAST_TINY = ["data.protocol=short", "training.epochs=1", "training.batch_size=64"]


@pytest.fixture
def baseline_run(small_registry, tmp_path) -> Path:
    return run_experiment(REPO / "experiments" / "baseline.yaml", small_registry, out=tmp_path / "run",
                          overrides=FAST_TINY, progress=False)


def _patches_of_rows(registry, unit: str, x: np.ndarray) -> set[int]:
    """The patch cells of the unit's rows whose pressures are the rows of x."""
    arr = load_arrays(registry, registry.list_runs(unit=unit))
    cell = {r.tobytes(): int(p) for r, p in zip(arr.pressure.astype(np.float64), arr.patch, strict=True)}
    return {cell[r.tobytes()] for r in np.ascontiguousarray(x)}


def test_baseline_held_out_patches_are_the_pipelines(baseline_run, small_registry):
    arrays = load_arrays(small_registry, small_registry.list_runs())
    split = per_unit_split(arrays, arrays.units, patch_test_mask(0.2, seed=0), 0.1, 0, torch.device("cpu"))
    for u, unit in enumerate(arrays.units[:3]):
        h = from_run(baseline_run, 0, unit, u, small_registry)
        assert h.patches == np.unique(arrays.patch[split.test_rows[u]]).tolist()
    with pytest.raises(AnytipError, match="random-rows model"):
        from_run(baseline_run, 0, arrays.units[0], len(arrays.units), small_registry)


def test_export_scores_only_rows_the_model_never_trained_on(baseline_run, small_registry, tmp_path, capsys):
    model = baseline_run / "models" / "per_unit_seed0" / "model.safetensors"
    unit = load_models(model).meta["unit_ids"][1]
    args = ["export", str(model), "--unit", unit, "--format", "onnx", "--registry", str(small_registry.root)]
    assert main([*args, "--out", str(tmp_path / "a")]) == 0
    rep = json.loads((tmp_path / "a" / "verification.json").read_text())["reference"]
    assert rep["rmse_may_include_training_rows"] is False and "warning" not in rep
    p = prepare(model, unit, small_registry, rows=10_000)
    held = set(from_run(baseline_run, 0, unit, 1, small_registry).patches)
    assert _patches_of_rows(small_registry, unit, p.ref.x) <= held
    arr = load_arrays(small_registry, small_registry.list_runs(unit=unit))
    in_contact = np.linalg.norm(arr.force, axis=1) > CONTACT_FORCE_N
    assert len(p.ref.x) == int((in_contact & np.isin(arr.patch, list(held))).sum())

    # the same file outside its run directory: nothing tells the held-out rows
    alone = tmp_path / "alone"
    alone.mkdir()
    for f in ("model.safetensors", "model.json"):
        shutil.copy(model.parent / f, alone / f)
    capsys.readouterr()
    assert main([*args[:1], str(alone / "model.safetensors"), *args[2:], "--out", str(tmp_path / "b")]) == 0
    rep = json.loads((tmp_path / "b" / "verification.json").read_text())["reference"]
    assert rep["rmse_may_include_training_rows"] is True and "may include training rows" in rep["warning"]
    assert "may include training rows" in capsys.readouterr().err
    # ... unless --held-out names the run
    assert main([*args[:1], str(alone / "model.safetensors"), *args[2:], "--out", str(tmp_path / "c"),
                 "--held-out", f"{baseline_run}:0"]) == 0
    rep = json.loads((tmp_path / "c" / "verification.json").read_text())["reference"]
    assert rep["rmse_may_include_training_rows"] is False and rep["held_out"]["patches"] == sorted(held)


def test_cross_sensor_run_and_folded_model_metadata(small_registry, tmp_path):
    unit = small_registry.units()[0]
    cells = np.unique(load_arrays(small_registry, small_registry.list_runs(unit=unit)).patch)[:2].tolist()
    run = tmp_path / "xs"
    model = save_baseline(run / "models" / "per_unit_seed3", n=1)
    meta = json.loads(model.with_suffix(".json").read_text())
    meta["meta"] |= {"unit_ids": [unit], "seed": 3}
    model.with_suffix(".json").write_text(json.dumps(meta))
    (run / "provenance.json").write_text(json.dumps(
        {"cross_sensor": {"seed3": {"test_patches": {unit: cells}}}}))
    h, why = for_model(model, load_models(model), 0, unit)
    assert h.patches == cells and why == ""
    p = prepare(model, unit, small_registry, rows=5000)
    assert p.ref.source == "registry, held out"
    assert _patches_of_rows(small_registry, unit, p.ref.x) <= set(cells)

    # a model folded by `anytip calibrate`: its calibration runs are not scored
    shared = tmp_path / "shared.json"
    shared.write_text(json.dumps({"meta": {"unit_ids": ["OTHER"]}}))
    runs = [r.run_id for r in small_registry.list_runs(unit=unit)]
    meta["meta"] |= {"shared_model": str(tmp_path / "shared.safetensors"), "calibration_runs": runs[:1]}
    folded = tmp_path / "folded" / "model.json"
    folded.parent.mkdir()
    folded.write_text(json.dumps(meta))
    shutil.copy(model, folded.with_suffix(".safetensors"))
    p = prepare(folded.with_suffix(".safetensors"), unit, small_registry)
    assert len(runs) > 1 and runs[0] not in p.ref.runs and set(runs[1:]) == set(p.ref.runs)
    assert not p.ref.may_include_training_rows
    shared.write_text(json.dumps({"meta": {"unit_ids": [unit]}}))  # the unit trained the shared model
    assert for_model(folded, load_models(folded.with_suffix(".safetensors")), 0, unit)[0] is None


def test_held_out_spec_and_errors(tmp_path):
    assert parse_spec("reports/cross_sensor:2") == (Path("reports/cross_sensor"), 2)
    assert parse_spec("runs/x") == (Path("runs/x"), None)
    with pytest.raises(AnytipError, match="provenance.json"):
        from_run(tmp_path, 0, "U0")
    (tmp_path / "provenance.json").write_text(json.dumps({"cross_sensor": {"seed0": {"test_patches": {}}}}))
    with pytest.raises(AnytipError, match="no held-out patches of unit 'U0'"):
        from_run(tmp_path, 0, "U0")
