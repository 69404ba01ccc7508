"""The realism pipeline: per-unit models against one model pooled over other units, scored on the
same held-out patches of the same held-out units."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from anytip.runner import run_experiment

REPO = Path(__file__).resolve().parents[1]
SPEC = REPO / "experiments" / "realism.yaml"
TINY = ["data.protocol=short", "data.max_units=8", "splits.n_test_units=2", "splits.n_train_units=6",
        "training.epochs=6"]


@pytest.fixture(scope="module")
def run(small_registry_master, tmp_path_factory):
    from anytip.data.registry import Registry

    out = tmp_path_factory.mktemp("realism") / "run"
    return run_experiment(SPEC, Registry(small_registry_master, create=False), out=out, overrides=TINY,
                          progress=False)


def test_pooled_and_per_unit_are_scored_on_the_same_held_out_units(run):
    rows = json.loads((run / "metrics.json").read_text())["results"]
    per_unit = {r["unit"]: r for r in rows if r["method"] == "per_unit"}
    pooled = {r["unit"]: r for r in rows if r["method"] == "pooled"}
    assert set(per_unit) == set(pooled) and len(per_unit) == 2
    roles = json.loads((run / "provenance.json").read_text())["unit_split"]["0"]
    assert set(per_unit) == set(roles["test"]) and not set(per_unit) & set(roles["train"])


def test_a_units_own_calibration_beats_a_model_of_other_units(run):
    """The default fleet's units differ: a model pooled over six other units errs more on a new
    unit than that unit's own model (the realism figure the simulator is tuned to)."""
    rows = json.loads((run / "metrics.json").read_text())["results"]
    ratio = [p["force_rmse_n"] / u["force_rmse_n"]
             for u in rows if u["method"] == "per_unit"
             for p in rows if p["method"] == "pooled" and p["unit"] == u["unit"]]
    assert len(ratio) == 2 and np.mean(ratio) > 1.5
    assert "pooled" in (run / "report.md").read_text()
