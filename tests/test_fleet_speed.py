"""The fleet_speed pipeline: one-by-one paper training, the fleet trainer with the paper recipe, and
the fleet trainer with the spec's recipe, timed to the same accuracy in one run."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from anytip.runner import run_experiment

REPO = Path(__file__).resolve().parents[1]
SPEC = REPO / "experiments" / "fleet_speed.yaml"
# Units with few rows (a protocol of a few presses) keep the one-by-one reference (batch 10) at seconds.
TINY = ["data.protocol=tiny", "training.epochs=4", "options.reference_evals_per_epoch=2"]


@pytest.fixture(scope="module")
def registry(tmp_path_factory):
    from anytip.data.registry import Registry
    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from anytip.sensor.protocols import Protocol

    reg = Registry(tmp_path_factory.mktemp("fleet_speed_registry"))
    tiny = Protocol(name="tiny", patches=4, layers_n=(12.5,), orientations_deg=(0.0,))
    simulate_into(reg, FleetConfig(), 3, seed=5, protocols=(tiny,))
    return reg


@pytest.fixture(scope="module")
def run(tmp_path_factory, registry):
    out = tmp_path_factory.mktemp("fleet_speed") / "run"
    return run_experiment(SPEC, registry, out=out, overrides=TINY, progress=False)


def test_three_methods_on_the_same_units_and_rows(run):
    rows = json.loads((run / "metrics.json").read_text())["results"]
    by_method = {}
    for r in rows:
        by_method.setdefault(r["method"], []).append(r)
    assert set(by_method) == {"per_unit_sequential", "per_unit_fleet", "per_unit_fleet_paper"}
    units = {m: sorted(r["unit"] for r in rs) for m, rs in by_method.items()}
    assert len({tuple(u) for u in units.values()}) == 1 and len(units["per_unit_fleet"]) == 3
    samples = {m: sorted(r["calib_samples"] for r in rs) for m, rs in by_method.items()}
    assert len({tuple(s) for s in samples.values()}) == 1  # every method trains on the same rows
    assert {r["recipe"] for r in by_method["per_unit_fleet_paper"]} == {"paper"}
    assert all(0 < r["force_rmse_n"] < 30 for r in rows)


def test_speed_ups_split_into_batching_and_recipe(run):
    s = json.loads((run / "provenance.json").read_text())["fleet_speed"]
    for key in ("reference_time_to_target_s", "fleet_time_to_target_s", "fleet_paper_time_to_target_s"):
        assert s[key] is None or s[key] > 0
    assert s["reference_time_to_target_s"] is not None  # the reference reaches its own final value
    if s["speedup_batching"] and s["speedup_recipe"]:
        assert s["speedup_time_to_target"] == pytest.approx(s["speedup_batching"] * s["speedup_recipe"])
    assert s["fleet_paper_time_to_target_s"] is None or \
        s["fleet_paper_time_to_target_s"] <= s["fleet_paper_total_train_s"]
    report = (run / "report.md").read_text()
    assert "all units at once, `paper` recipe" in report and "batching alone" in report
    assert (run / "time_to_accuracy.png").is_file()


def test_the_paper_fleet_can_be_left_out(registry, tmp_path):
    out = run_experiment(SPEC, registry, out=tmp_path / "r",
                         overrides=[*TINY, "options.fleet_paper=false"], progress=False)
    rows = json.loads((out / "metrics.json").read_text())["results"]
    assert {r["method"] for r in rows} == {"per_unit_sequential", "per_unit_fleet"}
    assert json.loads((out / "provenance.json").read_text())["fleet_speed"]["speedup_batching"] is None
