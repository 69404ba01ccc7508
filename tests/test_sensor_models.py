"""Sensor models other than the fingertip: a lab's 4-barometer edge sensor written from the format
spec alone (tests/fixtures/edge4), and the simulator's edge and pad sensors, through import,
the training arrays, the per-unit baseline with the committed spec, and export."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from anytip.data.arrays import BLOCKS_PER_RUN, REST_S, load_arrays
from anytip.data.registry import Registry
from anytip.data.simulated import regenerate, simulate_flat_into
from anytip.deploy.export import export_model
from anytip.errors import AnytipError
from anytip.runner import rewrite_report, run_experiment
from anytip.sensor import flat

REPO = Path(__file__).resolve().parents[1]
FIXTURE = REPO / "tests" / "fixtures" / "edge4"
BASELINE = REPO / "experiments" / "baseline.yaml"


@pytest.fixture(scope="module")
def lab(tmp_path_factory) -> Registry:
    reg = Registry(tmp_path_factory.mktemp("lab") / "reg")
    reg.import_paths([FIXTURE])
    return reg


@pytest.fixture(scope="module")
def lab_baseline(lab, tmp_path_factory) -> Path:
    return run_experiment(BASELINE, lab, out=tmp_path_factory.mktemp("run") / "baseline", progress=False)


def test_the_fixture_imports_with_its_layout(lab):
    assert lab.units() == ["LAB-E1", "LAB-E2", "LAB-E3"]
    channels, = {r.channels for r in lab.list_runs()}
    assert channels == 4
    layout = json.loads(lab.sensor_models()["edge-4baro-lab"])
    assert layout == {"channels": 4, "targets": {"depth": {"unit": "m", "components": ["z"]},
                                                 "position": {"unit": "m", "components": ["x"]}}}


def test_a_run_without_in_contact_labels_every_row_and_tares_from_its_first_half_second(lab):
    rec, = lab.list_runs(unit="LAB-E3")
    arrays = load_arrays(lab, [rec])
    with h5py.File(FIXTURE / "LAB-E3.h5") as f:
        assert "in_contact" not in f
        raw, time = f["pressure"][()].astype(np.float64), f["time"][()]
    assert arrays.n_rows == len(raw)
    np.testing.assert_allclose(arrays.tare[0], raw[time < REST_S].mean(0))
    np.testing.assert_allclose(arrays.pressure, (raw - arrays.tare[0]).astype(np.float32))


def test_runs_with_in_contact_keep_only_contact_rows_as_labels(lab):
    recs = lab.list_runs(unit="LAB-E1")
    arrays = load_arrays(lab, recs)
    with h5py.File(FIXTURE / "LAB-E1.h5") as f:
        contact = f["in_contact"][()]
        depth = f["targets/depth"][()]
    assert arrays.n_rows == contact.sum()
    np.testing.assert_array_equal(arrays.target("depth"), depth[contact])


def test_the_blocked_split_cuts_each_run_into_contiguous_blocks(lab):
    arrays = load_arrays(lab, lab.list_runs())
    for k in range(len(arrays.runs)):
        patch = arrays.patch[arrays.run == k]
        assert np.all(np.diff(patch) >= 0) and set(patch) == set(range(BLOCKS_PER_RUN))
        sizes = np.bincount(patch)
        assert sizes.max() - sizes.min() <= 1


def test_the_committed_baseline_spec_trains_the_edge_sensor(lab_baseline):
    rows = json.loads((lab_baseline / "metrics.json").read_text())["results"]
    config = (lab_baseline / "config.yaml").read_text()
    assert "- 4\n  - 12\n  - 64\n  - 64\n  - 2\n" in config  # widths from the sensor model
    assert {r["split"] for r in rows} == {"blocks", "random"}
    held = [r for r in rows if r["split"] == "blocks"]
    keys = {"position_rmse", "depth_rmse", "x_rmse", "z_rmse"}
    assert len(held) == 3 and all(keys <= r.keys() for r in held)
    # the labels spread over about 8 mm of position and 0.45 mm of depth; a model that learnt
    # nothing would err by that much
    assert np.mean([r["position_rmse"] for r in held]) < 0.2 * 8e-3
    assert np.mean([r["depth_rmse"] for r in held]) < 0.2 * 0.45e-3
    report = (lab_baseline / "report.md").read_text()
    assert "held-out blocks" in report and "position / spread" in report


def test_the_edge_model_exports_to_c_and_onnx_verified_and_the_firmware_struct_is_refused(
        lab, lab_baseline, tmp_path):
    model = lab_baseline / "models" / "per_unit_seed0" / "model.safetensors"
    for fmt in ("c", "onnx"):
        report = export_model(model, fmt, tmp_path / fmt, unit="LAB-E2", registry=lab)
        assert report["passed"], report
        assert set(report["scores"]) == {"depth_rmse", "position_rmse"}
    header = next((tmp_path / "c").glob("*.h")).read_text()
    assert "(N, rad)" not in header and "the unit of its target" in header
    with pytest.raises(AnytipError, match=r"firmware struct is the fingertip's.*outputs z, x from 4 baro"):
        export_model(model, "firmware", tmp_path / "fw", unit="LAB-E2", registry=lab)
    assert not (tmp_path / "fw" / "firmware.json").exists()


def test_explicit_widths_that_disagree_with_the_sensor_model_are_refused(lab, tmp_path):
    with pytest.raises(AnytipError, match=r"model.sizes.*input width 8 must equal the 4 pressure channels"):
        run_experiment(BASELINE, lab, out=tmp_path / "x", overrides=["model.sizes=[8, 12, 64, 64, 5]"],
                       progress=False)
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("model", sorted(flat.DESIGNS))
def test_simulated_flat_sensors_are_deterministic_v2_runs(model, tmp_path):
    reg = Registry(tmp_path / "reg")
    assert simulate_flat_into(reg, model, 2, 5, ("quick",)) == (2, 0)
    assert simulate_flat_into(reg, model, 2, 5, ("quick",)) == (0, 2)
    design = flat.get_design(model)
    rec = reg.list_runs()[0]
    run = reg.open_run(rec.run_id)
    assert run.format_version == 2 and run.n_channels == design.channels
    assert {n: (t.unit, t.components) for n, t in run.target_layout.items()} == \
        {n: (u, c) for n, u, c in design.targets}
    assert regenerate(run.extra["simulator"]).content_hash() == run.content_hash()
    assert not run.in_contact[: int(REST_S * run.sample_rate_hz)].any()


def test_flat_sensor_units_differ_and_severity_scales_it():
    design = flat.get_design("pad-16baro")

    def spread(severity: float) -> float:
        gains = [flat.draw_unit(design, np.random.default_rng(i), severity).gain for i in range(40)]
        return float(np.std(gains))

    assert spread(0.0) == 0.0
    assert 1.5 < spread(2.0) / spread(1.0) < 2.5


def test_pressure_grows_with_load_and_peaks_under_the_contact():
    design = flat.get_design("pad-16baro")
    unit = flat.draw_unit(design, np.random.default_rng(0), 0.0)
    xy = np.array([design.baro_xy_m[5]] * 2)
    p = flat.layer_pressure(xy, np.array([[0, 0, -2.0], [0, 0, -4.0]]), unit, design.tip_radius_m)
    assert np.argmax(p[0]) == 5 and np.all(p[1] > p[0]) and np.all(p > 0)


@pytest.mark.parametrize("model", sorted(flat.DESIGNS))
def test_the_baseline_trains_each_simulated_sensor_model(model, tmp_path):
    reg = Registry(tmp_path / "reg")
    simulate_flat_into(reg, model, 2, 1, ("short",))
    run_dir = run_experiment(BASELINE, reg, out=tmp_path / "run", progress=False,
                             overrides=["training.epochs=3", "data.protocol=short"])
    rows = json.loads((run_dir / "metrics.json").read_text())["results"]
    keys = {flat.get_design(model).targets[k][0] for k in range(2)}
    assert all({f"{k}_rmse" if k != "force" else "force_rmse_n" for k in keys} <= r.keys() for r in rows)


@pytest.fixture(scope="module")
def two_designs(tmp_path_factory) -> Registry:
    reg = Registry(tmp_path_factory.mktemp("designs") / "reg")
    for model in ("edge-4baro", "pad-16baro"):
        simulate_flat_into(reg, model, 8, 2, ("quick", "short"))
    return reg


def test_the_sensor_models_spec_runs_baseline_and_adapters_on_each_design(two_designs, tmp_path):
    spec = REPO / "experiments" / "sensor_models.yaml"
    run_dir = run_experiment(spec, two_designs, out=tmp_path / "run", progress=False, overrides=[
        "training.epochs=1", "data.protocol=[quick, short]", "options.cross_sensor.budgets=[0, 200]",
        "options.cross_sensor.adapters=[input_affine+film]", "options.cross_sensor.priors=[10]"])
    rows = json.loads((run_dir / "metrics.json").read_text())["results"]
    assert {(r["sensor_model"], r["stage"]) for r in rows} == {
        (m, s) for m in ("edge-4baro", "pad-16baro") for s in ("baseline", "cross_sensor")}
    edge = [r for r in rows if r["sensor_model"] == "edge-4baro" and r["stage"] == "cross_sensor"]
    assert {"adapted:input_affine+film", "per_unit"} <= {r["method"] for r in edge}
    assert all("position_rmse" in r and "depth_rmse" in r and r["split"] == "blocks" for r in edge)
    pad = [r for r in rows if r["sensor_model"] == "pad-16baro"]
    assert all("force_rmse_n" in r and "position_rmse" in r for r in pad)
    report = (run_dir / "report.md").read_text()
    assert "| budget | edge-4baro | pad-16baro |" in report
    pad_report = run_dir / "pad-16baro" / "cross_sensor" / "report.md"
    assert "position" in report and pad_report.is_file()
    before = pad_report.read_text()
    pad_report.unlink()
    rewrite_report(run_dir)  # from the recorded rows alone
    assert (run_dir / "report.md").read_text() == report and pad_report.read_text() == before


def test_search_runs_on_the_pad_with_an_objective_per_target(two_designs, tmp_path):
    overrides = ["data.sensor_model=pad-16baro", "data.protocol=short", "training.epochs=1",
                 "options.n_trials=3", "options.n_search_units=2", "options.n_test_units=2"]
    run_dir = run_experiment(REPO / "experiments" / "search.yaml", two_designs, out=tmp_path / "s",
                             progress=False, overrides=overrides)
    rows = json.loads((run_dir / "metrics.json").read_text())["results"]
    assert rows and all({"force_rmse_n", "position_rmse"} <= r.keys() for r in rows)
    assert all(r["sizes"][0] == 16 and r["sizes"][-1] == 5 and r["features"] == "raw" for r in rows)
    table = json.loads((run_dir / "provenance.json").read_text())["search"]["table"]
    assert all("position_rmse" in t and "angle_rmse_rad" not in t for t in table)
    assert "left out" in (run_dir / "report.md").read_text()


def test_realism_is_refused_for_other_designs_before_any_work(two_designs, tmp_path):
    with pytest.raises(AnytipError, match=r"written for the fingertip's targets.*'edge-4baro' has depth"):
        run_experiment(REPO / "experiments" / "realism.yaml", two_designs, out=tmp_path / "x", progress=False,
                       overrides=["data.sensor_model=edge-4baro", "data.protocol=short"])
    assert not (tmp_path / "x").exists()


def test_uncertainty_runs_on_the_edge_sensor_with_coverage_per_target(two_designs, tmp_path):
    run_dir = run_experiment(REPO / "experiments" / "uncertainty.yaml", two_designs, out=tmp_path / "u",
                             progress=False, overrides=[
                                 "data.sensor_model=edge-4baro", "data.protocol=[quick, short]",
                                 "training.epochs=1", "options.members=2", "options.bootstrap=10",
                                 "options.cv_folds=2", "options.max_train_rows=3000",
                                 "options.foreign_units=1",
                                 "options.adapted.epochs=1", "options.adapted.scale_epochs=1",
                                 "options.adapted.budget=500", "options.adapted.calib_rows=500",
                                 "splits.n_val_units=2", "splits.n_test_units=2"])
    rows = json.loads((run_dir / "metrics.json").read_text())["results"]
    cover = [r for r in rows if r.get("nominal_coverage") == 0.9 and r["method"] == "conformal"]
    assert {r["group"] for r in cover} == {"x", "z", "position", "depth"}
    assert {r["group"] for r in cover if r["target_group"]} == {"position", "depth"}
    assert all(0.5 < r["coverage"] <= 1.0 and "position_rmse" in r for r in cover)
    assert any(r["method"].startswith("adapted:") for r in rows)
    assert not any("fscale" in r["method"] for r in rows)  # a + b |F| needs a force target
    report = (run_dir / "report.md").read_text()
    assert "foreign-unit faults skipped" in report and "coverage_map" not in report


def test_another_shared_shape_takes_the_edge_sensors_ends(two_designs, tmp_path):
    """`options.shared_model` and `options.reference_shapes` name hidden widths only: on the
    4-barometer edge sensor the shapes take its 4 channels and its outputs, and fold there."""
    from anytip.calibrate import find_shared
    from anytip.models.io import load_models, load_shared

    overrides = ["data.sensor_model=edge-4baro", "data.protocol=[quick, short]", "seeds=[0]",
                 "training.epochs=1", "options.budgets=[0, 200]", "options.adapters=[input_affine+film]",
                 "options.priors=[10]", "options.sweep_seeds=0", "splits.n_val_units=1",
                 "splits.n_test_units=2", "options.shared_model={hidden: [16, 24]}",
                 "options.reference_shapes=[{hidden: [16, 24]}]"]
    run = run_experiment(REPO / "experiments" / "cross_sensor.yaml", two_designs, out=tmp_path / "run",
                         progress=False, overrides=overrides)
    shared = load_shared(find_shared(run, "input_affine+film")[0]).model
    assert shared.config.sizes[:3] == (4, 16, 24) and shared.config.sizes[-1] == 2
    assert load_models(run / "models" / "per_unit_4-16-24-2_seed0").model.config.sizes == (4, 16, 24, 2)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    assert {r["unit"] for r in rows if r["method"] == "per_unit:4-16-24-2"} == {
        r["unit"] for r in rows if r["method"] == "per_unit"}
