"""The cross-sensor pipeline and `anytip calibrate` on a tiny fleet: roles, no leakage,
folded models, the deployment workflow end to end."""

import dataclasses
import importlib.util
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import torch

from anytip.calibrate import calibrate_unit, find_shared
from anytip.cli import main
from anytip.config import DataConfig, load_spec
from anytip.data.arrays import load_arrays
from anytip.data.registry import Registry
from anytip.data.simulated import simulate_flat_into, simulate_into
from anytip.errors import AnytipError
from anytip.models.io import SHARED_FORMAT, load_models, load_shared, read_header
from anytip.pipelines.common import Context, load_extra
from anytip.pipelines.cross_sensor import main_rows, prepare
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.runner import run_experiment
from anytip.sensor.fleet import FleetConfig
from anytip.train.metrics import predict
from conftest import QUICK

REPO = Path(__file__).resolve().parents[1]
SPEC = REPO / "experiments" / "cross_sensor.yaml"
TINY = ["seeds=[0]", "training.epochs=1", "training.batch_size=128", "options.budgets=[0,50,400]",
        "options.adapters=[input_diag,input_affine+film]", "options.priors=[1,100]",
        "options.calibration_protocol=quick", "options.train_unit_counts=[2]",
        "options.adapter_steps=60", "options.scratch.epochs=5", "splits.n_val_units=1",
        "splits.n_test_units=2"]


@pytest.fixture(scope="module")
def cross_run(two_protocol_registry, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("run") / "cross"
    return run_experiment(SPEC, two_protocol_registry, out=out, overrides=TINY, progress=False)


def prepared(registry, tmp_path, overrides):
    """(options, arrays, seed-0 roles and tensors) of the spec with `overrides` on `registry`."""
    ctx = Context(load_spec(SPEC, overrides), registry, tmp_path, torch.device("cpu"), False)
    opts = parse_options(ctx)
    arrays = load_arrays(registry, registry.list_runs())
    return opts, arrays, prepare(ctx, arrays, opts, seed=0)


def test_held_out_units_and_patches_never_reach_training(two_protocol_registry, tmp_path):
    opts, arrays, sd = prepared(two_protocol_registry, tmp_path, TINY)
    assert set(sd.split.train).isdisjoint([*sd.split.val, *sd.split.test])
    assert sd.train.unit_ids == list(sd.split.train)
    train_rows = {r.tobytes() for u in range(sd.train.n_units) for X in (sd.train.unit(u).X_train,
                  sd.train.unit(u).X_val) for r in X.numpy()}
    main = main_rows(arrays, "quick")
    for unit, ev in sd.evals.items():
        own = arrays.unit == arrays.units.index(unit)
        assert own[ev.test_rows].all() and main[ev.test_rows].all()
        test_cells = set(arrays.patch[ev.test_rows])
        assert test_cells.isdisjoint(arrays.patch[ev.stream.rows])  # calibration never sees them
        assert not main[ev.stream.rows].any()  # the stream is the quick protocol's rows
        assert np.all(np.diff(ev.stream.seconds) >= 0)
        assert not train_rows & {r.tobytes() for r in arrays.pressure[own]}


def test_run_rows_follow_the_contract(cross_run):
    rows = json.loads((cross_run / "metrics.json").read_text())["results"]
    prov = json.loads((cross_run / "provenance.json").read_text())
    test_units = set(prov["cross_sensor"]["seed0"]["units"]["test"])
    methods = {r["method"] for r in rows}
    assert {"per_unit", "scratch", "pooled", "adapted:input_stats", "adapted:input_diag",
            "adapted:input_affine+film"} <= methods
    for r in rows:
        assert r["unit"] in test_units and np.isfinite(r["force_rmse_n"]) and r["seed"] == 0
        for key in ("method", "unit", "calib_samples", "seed", "force_rmse_n", "angle_rmse_rad"):
            assert key in r
    zero = {r["method"] for r in rows if r["calib_samples"] == 0}
    assert {"pooled", "adapted:input_stats"} <= zero
    budgets = {r["calib_samples"] for r in rows if r["method"] == "adapted:input_diag"}
    assert budgets == {0, 50, 400}
    assert {r["n_train_units"] for r in rows} == {2, 5}  # the unit-count sweep and the full set
    report = (cross_run / "report.md").read_text()
    assert "Targets" in report and (cross_run / "rmse_vs_budget.png").is_file()
    assert (cross_run / "ratio_vs_budget.png").is_file() and "ratio_vs_budget.png" in report


def test_saved_shared_model_folds_like_it_predicts(cross_run):
    shared = load_shared(find_shared(cross_run, "input_affine+film")[0])
    model = shared.model
    x = torch.randn(model.n_units, 50, 8)
    torch.testing.assert_close(model.fold()(x), model(x), atol=1e-5, rtol=1e-5)
    assert shared.meta["calibration_protocol"] == "quick" and shared.meta["priors_by_budget"]


def test_calibrate_writes_a_folded_per_unit_model(cross_run, two_protocol_registry, tmp_path, capsys):
    prov = json.loads((cross_run / "provenance.json").read_text())
    unit = prov["cross_sensor"]["seed0"]["units"]["test"][0]
    code = main(["calibrate", "--model", str(cross_run), "--unit", unit, "--budget-samples", "300",
                 "--registry", str(two_protocol_registry.root), "--out", str(tmp_path / "cal")])
    assert code == 0
    out = capsys.readouterr().out
    assert f"calibrated {unit}: 300 labeled samples" in out and "other runs" in out
    record = json.loads((tmp_path / "cal" / "calibration.json").read_text())
    assert record["core_gflops"] > 0 and f"fitted and folded in {record['wall_s']:.1f} s, on a core" in out
    loaded = load_models(tmp_path / "cal")
    assert loaded.model.n_models == 1 and loaded.meta["unit_ids"] == [unit]
    assert loaded.model.config.sizes == (8, 12, 64, 64, 5)
    assert loaded.meta["adapter"] in ("input_diag", "input_affine+film")
    assert loaded.meta["calib_samples"] == 300
    assert "lowest validation-unit loss" in out
    arrays = load_arrays(two_protocol_registry, two_protocol_registry.list_runs(unit=unit))
    pred = predict(loaded.model, loaded.in_scaler, loaded.out_scaler, torch.from_numpy(arrays.pressure)[None])
    assert torch.isfinite(pred).all()
    check = loaded.meta["check_on_other_runs"]
    assert check["rows"] > 0 and check["force_rmse_n"] < 20


def test_calibrate_label_free_and_by_seconds(cross_run, two_protocol_registry, tmp_path):
    unit = two_protocol_registry.list_runs()[0].unit
    zero = calibrate_unit(cross_run, unit, two_protocol_registry, tmp_path / "zero", budget_samples=0)
    assert zero.calib_samples == 0 and zero.unlabeled_samples > 0
    timed = calibrate_unit(cross_run, unit, two_protocol_registry, tmp_path / "t", budget_seconds=3.0)
    assert 0 < timed.calib_samples and timed.calib_seconds <= 3.0


def test_calibrate_errors_name_what_is_wrong(cross_run, two_protocol_registry, tmp_path):
    with pytest.raises(AnytipError, match="no runs of unit 'NOPE-1'"):
        calibrate_unit(cross_run, "NOPE-1", two_protocol_registry, tmp_path)
    with pytest.raises(AnytipError, match="no shared model for adapter 'film'"):
        find_shared(cross_run, "film")
    with pytest.raises(AnytipError, match="no config.yaml"):
        find_shared(tmp_path)
    with pytest.raises(AnytipError, match="not both"):
        calibrate_unit(cross_run, "x", two_protocol_registry, tmp_path, budget_samples=5, budget_seconds=1.0)


def test_unknown_option_is_refused(two_protocol_registry, tmp_path):
    with pytest.raises(AnytipError, match="options.*'budget' is not allowed.*budgets"):
        run_experiment(SPEC, two_protocol_registry, out=tmp_path, overrides=[*TINY, "options.budget=3"],
                       progress=False)


def test_designed_scale_reads_a_longer_design_never_a_shorter_one():
    from pydantic import ValidationError

    from anytip.pipelines.cross_sensor_options import Options
    assert Options().designed_scale == 1.0 and Options(designed_scale=1.25).designed_scale == 1.25
    with pytest.raises(ValidationError, match="designed_scale"):
        Options(designed_scale=0.8)


def test_runs_on_a_registry_of_short_runs_only(small_registry, tmp_path):
    """Units with only calibration-protocol runs are tested on held-out patches of those runs;
    their calibration budgets never touch them."""
    overrides = [o for o in TINY if not o.startswith("options.calibration_protocol")]
    overrides += ["options.sweep_seeds=0", "options.adapters=[input_diag]"]
    run = run_experiment(SPEC, small_registry, out=tmp_path / "run", overrides=overrides, progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    assert {"per_unit", "pooled", "adapted:input_stats", "adapted:input_diag"} <= {r["method"] for r in rows}
    assert all(np.isfinite(r["force_rmse_n"]) for r in rows)


def test_interleaved_stream_takes_the_orientations_in_turn(small_registry):
    """The same rows and robot time as the runs one after the other, but the first visits
    already come from every run (orientation)."""
    from anytip.data.calibration import calibration_stream

    arrays = load_arrays(small_registry, small_registry.list_runs())
    unit = arrays.units[0]
    plain = calibration_stream(arrays, unit, "short")
    mixed = calibration_stream(arrays, unit, "short", interleave=True)
    assert sorted(plain.rows.tolist()) == sorted(mixed.rows.tolist())
    assert mixed.seconds[-1] == pytest.approx(plain.seconds[-1]) and np.all(np.diff(mixed.seconds) >= 0)
    n_runs = len(plain.runs)
    assert n_runs > 1 and len(np.unique(arrays.run[plain.first(len(plain.rows) // n_runs)])) == 1
    assert len(np.unique(arrays.run[mixed.first(len(mixed.rows) // n_runs)])) == n_runs


def _val_loss_at(path: Path, budget: int) -> float:
    table = {int(b): v for b, v in json.loads(path.with_suffix(".json").read_text())["meta"]
             ["val_loss_by_budget"].items()}
    return table[max(b for b in table if b <= budget)]


def test_calibrate_picks_the_adapter_with_the_lowest_validation_loss(cross_run, two_protocol_registry,
                                                                     tmp_path):
    """A run without the default (sweep) adapter's model: the run's best adapter on validation
    units is taken, and calibrate says which and why."""
    import shutil

    run = tmp_path / "run"
    shutil.copytree(cross_run, run)
    for f in (run / "models").glob("shared_input_affine-film_*"):
        f.unlink()
    have = sorted((run / "models").glob("shared_*_seed0.safetensors"))
    for budget in (0, 50, 400):
        best = min(have, key=lambda p, b=budget: _val_loss_at(p, b))
        path, why = find_shared(run, budget=budget)
        assert path == best and "lowest validation-unit loss" in why, budget
    unit = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]["test"][0]
    result = calibrate_unit(run, unit, two_protocol_registry, tmp_path / "cal", budget_samples=50)
    chosen = min(have, key=lambda p: _val_loss_at(p, 50))
    assert any(chosen.name in n and "<= 50 labeled samples" in n for n in result.notes)


def test_calibrate_reports_clipped_budgets_and_training_units(cross_run, two_protocol_registry, tmp_path,
                                                              capsys):
    prov = json.loads((cross_run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]
    code = main(["calibrate", "--model", str(cross_run), "--unit", prov["train"][0], "--budget-samples",
                 "999999", "--registry", str(two_protocol_registry.root), "--out", str(tmp_path / "c")])
    out, err = capsys.readouterr()
    assert code == 0 and "clipped to the" in out and "was a training unit" in err
    code = main(["calibrate", "--model", str(cross_run), "--unit", prov["train"][0], "--budget-samples",
                 "10", "--registry", str(two_protocol_registry.root), "--out", str(tmp_path / "c")])
    assert code == 2 and "--force" in capsys.readouterr().err


@pytest.mark.parametrize(("key", "value"), [("options", "5"), ("seeds", "'x'"), ("seed", "[1]")])
def test_calibrate_refuses_a_damaged_run_config(cross_run, two_protocol_registry, tmp_path, capsys, key,
                                                value):
    import shutil

    run = tmp_path / "run"
    shutil.copytree(cross_run, run)
    config = (run / "config.yaml").read_text()
    (run / "config.yaml").write_text(config + f"\n{key}: {value}\n" if key not in config.split(":")[0]
                                     else __import__("re").sub(rf"(?m)^{key}:.*$", f"{key}: {value}", config))
    code = main(["calibrate", "--model", str(run), "--unit", "x", "--registry",
                 str(two_protocol_registry.root), "--out", str(tmp_path / "c")])
    err = capsys.readouterr().err
    assert code == 2 and "config.yaml" in err and key in err and "Traceback" not in err


SECONDS = [*TINY[:3], "options.budget_unit=seconds", "options.budgets=[0,8,40]",
           "options.plan_strategies=[first,spread]", "options.adapters=[input_affine+film]",
           "options.priors=[1,100]", "options.calibration_protocol=null", "options.adapter_steps=60",
           "options.adapter_priors=[identity,empirical]", "options.reference_lrs=[0.003,0.01]",
           "options.reference_starts=2",
           "options.reference_val=patches", "options.unlabeled_s=20",
           "options.scratch.epochs=5", "options.sweep_seeds=0", "splits.n_val_units=1",
           "splits.n_test_units=2", "options.fits=[{}, {add: lowrank2, steps: 30}]",
           "options.intervals={folds: 3, level: 0.8}"]


@pytest.fixture(scope="module")
def seconds_run(two_protocol_registry, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("run") / "seconds"
    return run_experiment(SPEC, two_protocol_registry, out=out, overrides=SECONDS, progress=False)


def test_budgets_in_seconds_are_whole_presses_within_the_robot_time(seconds_run):
    rows = json.loads((seconds_run / "metrics.json").read_text())["results"]
    timed = [r for r in rows if "budget_s" in r and r["budget_s"] > 0]
    methods = ("scratch", "adapted:input_affine+film", "adapted:input_affine+film/empirical",
               "adapted:input_affine+film+lowrank2[30 steps]")  # no empirical prior for an added part
    assert {r["method"] for r in timed} == {f"{m}@{s}" for m in methods for s in ("first", "spread")}
    refs = [r for r in rows if r["method"] == "per_unit"]
    assert refs and all(r["reference_lr"] in (0.003, 0.01) and r["reference_start"] in (0, 1) for r in refs)
    fits = sorted(p.name for p in (seconds_run / "models").glob("per_unit_seed0_*"))
    assert fits == ["per_unit_seed0_lr0", "per_unit_seed0_lr0_start1", "per_unit_seed0_lr1",
                    "per_unit_seed0_lr1_start1"]
    for r in timed:
        assert 0 < r["calib_seconds"] <= r["budget_s"] and r["presses"] >= 1
        assert r["n_effective"] <= r["calib_samples"]
        if not r["method"].startswith("scratch"):
            assert 0 < r["unlabeled_seconds"] <= 20
    big = [r for r in timed if r["budget_s"] == 40]
    assert all(r["presses"] > 1 for r in big)
    report = (seconds_run / "report.md").read_text()
    assert "robot seconds of whole presses" in report and "<= 120 s of robot time" in report
    assert "chosen on validation units" in report
    record = json.loads((seconds_run / "provenance.json").read_text())["cross_sensor"]["seed0"]
    val = record["val_loss"]
    assert set(val["adapted:input_affine+film@spread"]) == {"8", "40"} and "0" in val["adapted:input_stats"]
    units = record["val_loss_units"]["adapted:input_affine+film@spread"]  # each validation unit's loss
    for budget, loss in val["adapted:input_affine+film@spread"].items():
        assert set(units[budget]) == set(record["units"]["val"])
        assert np.mean(list(units[budget].values())) == pytest.approx(loss)
    meta = load_shared(find_shared(seconds_run, "input_affine+film")[0]).meta
    assert meta["budget_unit"] == "seconds" and meta["plan_strategy"] == "spread"
    assert set(meta["priors_by_budget"]) == {"8", "40"}


def test_plans_never_touch_test_patches(two_protocol_registry, tmp_path):
    from anytip.pipelines.cross_sensor import plan_of
    from anytip.pipelines.cross_sensor_options import budget_list

    opts, arrays, sd = prepared(two_protocol_registry, tmp_path, SECONDS)
    from anytip.data.calibration import calibration_stream
    from anytip.train.adapt import input_stats

    first = calibration_stream(arrays, sd.split.train[0], None)  # training units read the same window
    want = input_stats([torch.from_numpy(arrays.pressure[first.unlabeled(opts.unlabeled_s)])])
    torch.testing.assert_close(sd.train_stats.mean[0], want.mean[0])
    for unit, ev in sd.evals.items():
        test_cells = set(arrays.patch[ev.test_rows])
        for b in budget_list(opts, [8.0, 40.0, 1e5]):
            plan = plan_of(sd, unit, b, opts, 0)
            assert test_cells.isdisjoint(arrays.patch[plan.rows])
            assert not np.isin(plan.rows, ev.test_rows).any()
            assert plan.calib_seconds <= b.amount


def test_calibrate_by_seconds_selects_presses_like_the_benchmark(seconds_run, two_protocol_registry, tmp_path,
                                                                 capsys):
    prov = json.loads((seconds_run / "provenance.json").read_text())
    unit = prov["cross_sensor"]["seed0"]["units"]["test"][0]
    result = calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "s", budget_seconds=40.0)
    assert 0 < result.calib_seconds <= 40.0
    own = result.own_check
    assert own["presses"] == result.own_check["presses"] >= 2 and own["standardised_mse"] > 0
    assert own["rows"] == result.calib_samples and own["folds"] == min(5, own["presses"])
    assert own["over_fleet"] == pytest.approx(own["standardised_mse"] / own["fleet_validation_mse"])
    loaded = load_models(tmp_path / "s")
    assert loaded.meta["calib_presses"] > 1 and loaded.meta["n_effective"] <= loaded.meta["calib_samples"]
    assert result.prior == loaded.meta["prior"]
    with pytest.raises(AnytipError, match="give --budget-seconds"):
        calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "x", budget_samples=100)
    assert main(["calibrate", "--model", str(seconds_run), "--unit", unit, "--budget-seconds", "40",
                 "--registry", str(two_protocol_registry.root), "--out", str(tmp_path / "cli")]) == 0
    out = capsys.readouterr().out
    assert "own check" in out and "not the same rows" in out and "fitted and folded in" in out
    assert "90% intervals from the plan (3 press folds" in out  # the folds its benchmark used


def test_calibrate_gives_intervals_from_the_units_own_plan(seconds_run, two_protocol_registry, tmp_path):
    """Every plan row predicted out of fold once; a half-width per output, wider at a higher
    level; their coverage of the unit's other runs; none when asked for none; a bad level refused."""
    prov = json.loads((seconds_run / "provenance.json").read_text())
    unit = prov["cross_sensor"]["seed0"]["units"]["test"][0]
    r = calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "a", budget_seconds=40.0,
                       interval_level=0.8)
    assert r.intervals["rows"] == r.calib_samples and r.intervals["level"] == 0.8
    names = ["fx", "fy", "fz", "theta", "phi"]
    assert list(r.intervals["halfwidth"]) == names and all(v > 0 for v in r.intervals["halfwidth"].values())
    assert "coverage_on_other_runs" not in r.intervals  # its plan may take presses of every run
    assert load_models(tmp_path / "a").meta["intervals"] == r.intervals
    wide = calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "b", budget_seconds=40.0,
                          interval_level=0.95)
    assert all(wide.intervals["halfwidth"][n] >= r.intervals["halfwidth"][n] for n in names)
    none = calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "c", budget_seconds=40.0,
                          interval_level=None)
    assert none.intervals is None and load_models(tmp_path / "c").meta["intervals"] is None
    with pytest.raises(AnytipError, match="--interval-level"):
        calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "d", budget_seconds=40.0,
                       interval_level=1.5)


def test_calibrate_applies_the_fleet_factor_its_benchmark_learnt(seconds_run, two_protocol_registry,
                                                                 tmp_path):
    """At the benchmark's level, calibrate cross-fits over the benchmark's interval folds and
    scales the plan's own half-width by the factor recorded for the largest budget <= its own;
    at another level it says why it applies none."""
    from anytip.calibrate import fleet_factor_for

    prov = json.loads((seconds_run / "provenance.json").read_text())
    unit = prov["cross_sensor"]["seed0"]["units"]["test"][0]
    meta = read_header(seconds_run / "models" / "shared_input_affine-film_seed0.json", SHARED_FORMAT)["meta"]
    r = calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "a", budget_seconds=40.0,
                       interval_level=0.8)
    band = r.intervals
    factor = meta["intervals"]["fleet_factor_by_budget"]["40"]
    assert band["folds"] == 3 and band["fleet_factor"] == factor
    for n, f in factor.items():
        assert band["halfwidth"][n] == pytest.approx(band["own_halfwidth"][n] * f)
    other = calibrate_unit(seconds_run, unit, two_protocol_registry, tmp_path / "b", budget_seconds=40.0,
                           interval_level=0.9)
    assert "fleet_factor" not in other.intervals and any("learnt at level 0.8" in n for n in other.notes)
    names = ("fx", "fy", "fz", "theta", "phi")
    assert fleet_factor_for({}, 40.0, 0.8, names) == (None, "")
    assert fleet_factor_for(meta, 1.0, 0.8, names)[0] is None  # below every recorded budget
    bad = {"intervals": {"level": 0.8, "folds": 3, "fleet_factor_by_budget": {"5": {"fx": -1.0}}}}
    assert "no usable fleet factor" in fleet_factor_for(bad, 40.0, 0.8, names)[1]


def test_plan_intervals_score_the_units_other_runs():
    """Half-widths from residuals; the other runs' rows inside them, per output; no residuals,
    no intervals."""
    from anytip.calibrate import plan_intervals

    resid = np.tile(np.arange(1.0, 11.0)[:, None], (1, 2))  # |r| = 1..10 in both outputs
    pred, target = np.zeros((4, 2)), np.array([[0.5, 9.5], [8.5, 10.5], [-9.5, 0.0], [20.0, 1.0]])
    bands = plan_intervals(resid, 0.8, ("a", "b"), (pred, target))
    assert bands["halfwidth"] == {"a": 9.0, "b": 9.0}  # the ceil(11 * 0.8) = 9th smallest
    assert bands["coverage_on_other_runs"] == {"a": 0.5, "b": 0.5} and bands["rows"] == 10
    assert "coverage_on_other_runs" not in plan_intervals(resid, 0.8, ("a", "b"), None)
    assert plan_intervals(None, 0.8, ("a", "b"), (pred, target)) is None


def test_a_lighter_ordinary_use_than_the_benchmarks_takes_the_plan_alones_factor():
    """The factor for codes fitted with use serves use that weighs the benchmark's seconds or more;
    below that the plan alone's, with a note naming both weights."""
    from anytip.calibrate.intervals import use_factor_fits

    notes: list[str] = []
    assert use_factor_fits(600.0, 600.0, notes) and use_factor_fits(700.0, 600.0, notes) and not notes
    assert not use_factor_fits(162.14, 600.0, notes)
    assert notes == ["intervals: the plan alone's fleet factor, as the ordinary use read weighs 162.1 s, "
                     "less than the 600 s the benchmark's factor for codes fitted with use was learnt on "
                     "(research log entry 198)"]


def test_calibrate_plan_writes_robot_waypoints(tmp_path, capsys):
    out = tmp_path / "plan.csv"
    assert main(["calibrate", "--plan", "120", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "112.3 s of robot time" in said
    assert "18 presses, one at each of 18 places, on 2 orientations" in said
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert table.dtype.names == ("time_s", "orientation_deg", "theta_deg", "phi_deg", "fx_n", "fy_n", "fz_n")
    assert np.all(np.diff(table["time_s"]) >= 0) and table["time_s"][-1] <= 120
    assert set(table["orientation_deg"]) == {0.0, -90.0}  # together they cover phi in [-135, 45]
    assert table["theta_deg"].min() >= -45 and table["theta_deg"].max() <= 45
    assert table["phi_deg"].min() >= -135 and table["phi_deg"].max() <= 45
    assert -table["fz_n"].max() >= 0 and -table["fz_n"].min() <= 25.0
    shear = np.hypot(table["fx_n"], table["fy_n"])
    assert shear.max() > 0 and np.all(shear <= 0.8 * -table["fz_n"] + 1e-9)
    assert main(["calibrate", "--plan", "120", "--out", str(out)]) == 2  # exists, no --force
    short = tmp_path / "p60.csv"  # a re-mount would take half of 60 s: the middle orientation alone
    assert main(["calibrate", "--plan", "60", "--out", str(short)]) == 0
    assert set(np.genfromtxt(short, delimiter=",", names=True)["orientation_deg"]) == {-45.0}
    assert main(["calibrate", "--plan", "1", "--out", str(tmp_path / "p1.csv")]) == 2
    assert "holds no press" in capsys.readouterr().err
    assert main(["calibrate", "--plan", "600", "--out", str(tmp_path / "p600.csv")]) == 0
    assert "128 presses, 4 force levels at each of 32 places, on 2 orientations" in capsys.readouterr().out
    drawn = tmp_path / "random.csv"  # the same presses and time, at cells and loads drawn at random
    assert main(["calibrate", "--plan", "120", "--plan-points", "random", "--out", str(drawn)]) == 0
    assert "18 presses, one at each of 18 places, on 2 orientations" in capsys.readouterr().out
    random_table = np.genfromtxt(drawn, delimiter=",", names=True)
    np.testing.assert_array_equal(random_table["time_s"], table["time_s"])
    assert not np.array_equal(random_table["theta_deg"], table["theta_deg"])


def test_a_finished_run_rewrites_its_report_from_its_records(seconds_run, tmp_path, capsys):
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(seconds_run, copy)
    before = (copy / "report.md").read_text()
    (copy / "report.md").unlink()
    assert main(["report", str(copy)]) == 0
    assert (copy / "report.md").read_text() == before
    prov = json.loads((copy / "provenance.json").read_text())  # a run that recorded no validation losses
    del prov["cross_sensor"]["seed0"]["val_loss"]
    (copy / "provenance.json").write_text(json.dumps(prov))
    assert main(["report", str(copy)]) == 0
    after = [line for line in (copy / "report.md").read_text().splitlines()
             if line.startswith("| <= 120 s of robot time, `spread`")]
    assert after and "`adapted:input_affine+film@spread` @ 40" in after[0]  # the saved models' losses
    (copy / "metrics.json").write_text("{not json")
    assert main(["report", str(copy)]) == 2
    assert "metrics.json: not a readable JSON file" in capsys.readouterr().err


@pytest.fixture(scope="module")
def extra_registry(tmp_path_factory) -> Registry:
    """Three more units of the same design (another fleet seed: no unit in common)."""
    registry = Registry(tmp_path_factory.mktemp("extra"))
    simulate_into(registry, FleetConfig(), 3, seed=12, protocols=(QUICK,))
    return registry


def test_extra_units_only_train(two_protocol_registry, extra_registry, tmp_path):
    """Units of `options.extra_units` join the shared model's training units, after the split's
    own, and never become validation or held-out units."""
    ctx = Context(load_spec(SPEC, TINY), two_protocol_registry, tmp_path, torch.device("cpu"), False)
    opts = parse_options(ctx)
    arrays = load_arrays(two_protocol_registry, two_protocol_registry.list_runs())
    ctx.provenance["sensor_model"] = arrays.runs[0].sensor_model
    extra = load_extra(ctx, str(extra_registry.root), DataConfig(protocol=None), arrays)
    sd = prepare(ctx, arrays, opts, seed=0, extra=extra)
    assert sd.n_extra == 3 and sd.train.unit_ids == [*sd.split.train, *extra.units]
    assert set(extra.units).isdisjoint([*sd.split.train, *sd.split.val, *sd.split.test, *sd.evals])
    assert sd.train_stats.mean.shape[0] == len(sd.split.train) + 3
    assert ctx.provenance["extra_units"]["units"] == extra.units


def test_a_run_with_extra_units_says_so(two_protocol_registry, extra_registry, tmp_path):
    overrides = [*TINY, "options.sweep_seeds=0", "options.adapters=[input_affine+film]",
                 f"options.extra_units={{registry: {extra_registry.root}}}"]
    run = run_experiment(SPEC, two_protocol_registry, out=tmp_path / "run", overrides=overrides,
                         progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    assert {r["n_extra_units"] for r in rows} == {3}
    assert "also trains on 3 units of registry" in (run / "report.md").read_text()


def test_extra_units_are_refused_when_they_overlap_or_differ(two_protocol_registry, tmp_path):
    same = Registry(tmp_path / "same")
    simulate_into(same, FleetConfig(), 2, seed=11, protocols=(QUICK,))  # the registry's own first units
    overrides = [*TINY, f"options.extra_units={{registry: {same.root}}}"]
    with pytest.raises(AnytipError, match=r"holds 2 units that the experiment's registry holds too \(SIM"):
        run_experiment(SPEC, two_protocol_registry, out=tmp_path / "a", overrides=overrides, progress=False)
    other = Registry(tmp_path / "edge")
    simulate_flat_into(other, "edge-4baro", 2, seed=3, protocols=("quick",))
    overrides = [*TINY, f"options.extra_units={{registry: {other.root}}}"]
    with pytest.raises(AnytipError, match="must hold sensor model 'fingertip-8baro-r10'.*no runs of it"):
        run_experiment(SPEC, two_protocol_registry, out=tmp_path / "b", overrides=overrides, progress=False)
    overrides = [*TINY, f"options.extra_units={{registry: {tmp_path / 'nothing'}}}"]
    with pytest.raises(AnytipError, match="not a registry"):
        run_experiment(SPEC, two_protocol_registry, out=tmp_path / "c", overrides=overrides, progress=False)


def test_the_benchmark_records_each_units_own_check(seconds_run):
    """Validation and held-out units' calibrations are checked on their own presses, as
    `anytip calibrate` checks a new unit; the shared model keeps the validation units' figures."""
    own = json.loads((seconds_run / "provenance.json").read_text())["cross_sensor"]["seed0"]["own_check"]
    checks = own["by_shared_model"]["input_affine-film"]
    units = json.loads((seconds_run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]
    assert set(checks) == {"8 s first", "8 s spread", "40 s first", "40 s spread"}
    assert set(checks["40 s spread"]) == {*units["val"], *units["test"]}
    assert all(v > 0 for v in checks["40 s spread"].values())
    meta = load_shared(seconds_run / "models" / "shared_input_affine-film_seed0.safetensors").meta
    assert meta["own_check_by_budget"]["40"] == [checks["40 s spread"][u] for u in units["val"]]
    assert meta["own_check_folds"] == 5 and own["folds"] == 5
    report = (seconds_run / "report.md").read_text()
    assert "## The calibration's own check on ordinary units" in report
    assert "| `input_affine-film` | 40 s spread | 2 |" in report  # 2 held-out units, one seed


def kgf_labelled_unit(registry: Registry, unit: str, name: str) -> None:
    """Add a copy of `unit`'s runs as unit `name` whose force labels are 9.81x too large (a rig
    log in kilogram-force imported as newtons)."""
    runs = []
    for rec in registry.list_runs(unit=unit):
        run = registry.open_run(rec.run_id)
        force = run.targets["force"]
        targets = {**run.targets, "force": dataclasses.replace(force, values=force.values * np.float32(9.81))}
        runs.append(dataclasses.replace(run, sensor_id=name, targets=targets))
    registry.add_runs(runs)


def test_calibrate_flags_a_unit_with_wrong_labels(seconds_run, two_protocol_registry, tmp_path, capsys):
    """Force labels in the wrong unit make the calibration's own check far worse than any
    validation unit's; `anytip calibrate` says so on stderr. The held-out unit they were
    copied from passes."""
    shutil.copytree(two_protocol_registry.root, tmp_path / "reg")
    registry = Registry(tmp_path / "reg")
    prov = json.loads((seconds_run / "provenance.json").read_text())
    unit = prov["cross_sensor"]["seed0"]["units"]["test"][0]
    kgf_labelled_unit(registry, unit, "SIM99-000")
    good = calibrate_unit(seconds_run, unit, registry, tmp_path / "good", budget_seconds=40.0)
    bad = calibrate_unit(seconds_run, "SIM99-000", registry, tmp_path / "bad", budget_seconds=40.0)
    assert bad.own_check["over_validation"] > 5 * good.own_check["over_validation"]
    assert bad.own_check["alarm"] and not good.own_check["alarm"]
    assert main(["calibrate", "--model", str(seconds_run), "--unit", "SIM99-000", "--budget-seconds", "40",
                 "--registry", str(registry.root), "--out", str(tmp_path / "cli")]) == 0
    captured = capsys.readouterr()
    assert "checked the same way" in captured.out and "(ALARM)" in captured.out
    assert "warning: the calibration's own check is" in captured.err


def test_a_shared_model_of_another_shape_folds_into_that_shape(two_protocol_registry, tmp_path, capsys):
    """`options.shared_model` sets the shape of the shared models (and what `anytip calibrate`
    writes); the per-unit reference keeps the spec's model, and `options.reference_shapes` adds
    per-unit models of other shapes beside it, scored against it."""
    overrides = [*TINY, "options.sweep_seeds=0", "options.adapters=[input_affine+film]",
                 "options.shared_model={hidden: [16, 24]}", "options.reference_shapes=[{hidden: [16, 24]}]"]
    run = run_experiment(SPEC, two_protocol_registry, out=tmp_path / "run", overrides=overrides,
                         progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    refs = {m: sorted(r["unit"] for r in rows if r["method"] == m)
            for m in ("per_unit", "per_unit:8-16-24-5")}
    assert refs["per_unit"] == refs["per_unit:8-16-24-5"] and len(refs["per_unit"]) == 2
    assert load_models(run / "models" / "per_unit_8-16-24-5_seed0").model.config.sizes == (8, 16, 24, 5)
    assert "| per_unit:8-16-24-5 | full |" in (run / "report.md").read_text()
    shared = load_shared(find_shared(run, "input_affine+film")[0])
    assert shared.model.config.sizes == (8, 16, 24, 5)
    x = torch.randn(shared.model.n_units, 50, 8)
    torch.testing.assert_close(shared.model.fold()(x), shared.model(x), atol=1e-5, rtol=1e-5)
    assert load_models(run / "models" / "per_unit_seed0").model.config.sizes == (8, 12, 64, 64, 5)
    assert "8 -> 16 -> 24 -> 5 MLP (`options.shared_model`)" in (run / "report.md").read_text()
    unit = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]["test"][0]
    code = main(["calibrate", "--model", str(run), "--unit", unit, "--budget-samples", "300",
                 "--registry", str(two_protocol_registry.root), "--out", str(tmp_path / "cal")])
    assert code == 0 and load_models(tmp_path / "cal").model.config.sizes == (8, 16, 24, 5)


def test_a_shared_model_whose_ends_disagree_is_refused(two_protocol_registry, tmp_path, capsys):
    overrides = [*TINY, "options.shared_model={sizes: [8, 16, 3]}"]
    code = main(["run", str(SPEC), "--registry", str(two_protocol_registry.root),
                 "--out", str(tmp_path / "r"), *[a for o in overrides for a in ("--set", o)]])
    err = capsys.readouterr().err
    assert code != 0 and "options.shared_model" in err and "output width" in err


def test_where_a_calibration_errs_recalibrates_like_the_benchmark(seconds_run, two_protocol_registry):
    """scripts/where_calibration_errs.py refits each held-out unit as the run did: its ratio on
    the test patches at the run's prior is the run's own row, and every unit gets a ratio on
    its plan's rows and at each prior asked for."""
    spec = importlib.util.spec_from_file_location("where", REPO / "scripts" / "where_calibration_errs.py")
    where = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(where)
    lines = where.seed_ratios(seconds_run, str(two_protocol_registry.root), 0, 40.0, "input_affine+film",
                              [1.0, 100.0])
    rows = json.loads((seconds_run / "metrics.json").read_text())["results"]
    ref = {r["unit"]: r["force_rmse_n"] for r in rows if r["method"] == "per_unit"}
    ran = {r["unit"]: (r["force_rmse_n"] / ref[r["unit"]], r["prior"]) for r in rows
           if r["method"] == "adapted:input_affine+film@spread" and r["budget_s"] == 40}
    assert sorted(line["unit"] for line in lines) == sorted(ran)
    for line in lines:
        assert line["plan"] > 0 and ("visited" in line or "unvisited" in line)
        assert set(line["by_prior"]) == {1.0, 100.0}
        ratio, prior = ran[line["unit"]]
        assert line["by_prior"][prior] == pytest.approx(ratio, rel=0.05)
    assert "best strength of each unit" in where.table(lines)

    def orientations(remount_s: float) -> list[int]:
        got = where.seed_ratios(seconds_run, str(two_protocol_registry.root), 0, 40.0, "input_affine+film",
                                [], remount_s=remount_s)
        return [len(line["orientations"]) for line in got]
    assert max(orientations(0.0)) > 1  # re-mounts for free: the plan spreads over orientations
    assert max(orientations(1e5)) == 1  # a plan that never re-mounts stays in one
    arrays = load_arrays(two_protocol_registry, two_protocol_registry.list_runs())
    some = np.flatnonzero(arrays.unit == 0)[:500]
    assert where.within_plan(arrays, some, some).all()  # a plan's own rows lie within its span
    moved = dataclasses.replace(arrays, labels=arrays.labels.copy())
    moved.labels[some[:10], 3] += 10.0  # theta far outside any plan
    assert not where.within_plan(moved, some[10:], some[:10]).any()


def test_episodic_training_is_its_own_method_and_calibrates(two_protocol_registry, tmp_path):
    """`options.shared_training: [joint, episodic]` trains each adapter kind both ways, side by
    side in one run: rows `adapted:<kind>~episodic`, their own validation losses and model file,
    the learnt inner step sizes in its history; `anytip calibrate` may pick either."""
    overrides = [*TINY, "options.sweep_seeds=0", "options.adapters=[input_affine+film]",
                 "options.shared_training=[joint,episodic]", "options.fits=[{}, {inner: true}]",
                 "options.episodic={presses: 2, rows_per_press: 8, inner_steps: 2}"]
    run = run_experiment(SPEC, two_protocol_registry, out=tmp_path / "run", overrides=overrides,
                         progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    methods = {r["method"] for r in rows}
    assert {"adapted:input_affine+film", "adapted:input_affine+film~episodic",
            "adapted:input_affine+film~episodic[inner fit]"} <= methods
    assert "adapted:input_affine+film[inner fit]" not in methods  # a joint model learnt no inner fit
    inner = [r for r in rows if r["method"] == "adapted:input_affine+film~episodic[inner fit]"]
    assert inner and all(r["prior"] in (None, 0.0) for r in inner)
    val = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["val_loss"]
    assert set(val["adapted:input_affine+film~episodic"]) == {"0", "50", "400"}
    path, _ = find_shared(run, "input_affine+film_episodic")
    shared = load_shared(path)
    assert "rates" not in shared.meta["adapter_recipe"]  # calibrate fits like the first fit: Adam
    x = torch.randn(shared.model.n_units, 50, 8)
    torch.testing.assert_close(shared.model.fold()(x), shared.model(x), atol=1e-5, rtol=1e-5)
    assert "adapted:input_affine+film~episodic" in (run / "report.md").read_text()


def test_calibrate_uses_the_inner_fit_an_episodic_model_learnt(two_protocol_registry, tmp_path):
    """With the inner fit first, the episodic model's file carries its learnt step sizes and
    `anytip calibrate` fits a new unit with them (full-batch steps, no prior)."""
    overrides = [*TINY, "options.sweep_seeds=0", "options.adapters=[input_affine+film]",
                 "options.shared_training=[episodic]", "options.fits=[{inner: true}]",
                 "options.budgets=[0,400]",
                 "options.episodic={presses: 2, rows_per_press: 8, inner_steps: 3}"]
    run = run_experiment(SPEC, two_protocol_registry, out=tmp_path / "run", overrides=overrides,
                         progress=False)
    path, _ = find_shared(run, "input_affine+film_episodic")
    meta = load_shared(path).meta
    assert meta["adapter_recipe"]["steps"] == 3 and set(meta["adapter_recipe"]["rates"]) >= {"in_A", "gamma0"}
    assert meta["priors_by_budget"] == {"400": 0.0}
    unit = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]["test"][0]
    code = main(["calibrate", "--model", str(path), "--unit", unit, "--budget-samples", "300",
                 "--registry", str(two_protocol_registry.root), "--out", str(tmp_path / "cal")])
    assert code == 0 and load_models(tmp_path / "cal").model.config.sizes == (8, 12, 64, 64, 5)


def test_run_diagnostic_frame_collects_every_seed_and_writes_its_text(seconds_run, tmp_path, capsys):
    """The scripts' shared frame: the run's own seeds unless asked, one text printed and written."""
    from anytip.pipelines.run_diagnostic import diagnose, diagnostic_parser

    out = tmp_path / "d.md"
    a = diagnostic_parser("A diagnostic.\n\nmore").parse_args([str(seconds_run), "--registry", "r",
                                                              "--out", str(out)])
    assert a.budget == 120.0 and a.adapter == "input_affine+film"
    text = diagnose(a, lambda s: [f"seed {s}"], lambda seeds, lines: f"{seeds}: {', '.join(lines)}")
    assert text == "[0]: seed 0" and out.read_text() == text and text in capsys.readouterr().out
    a = diagnostic_parser("d").parse_args([str(seconds_run), "--registry", "r", "--seeds", "3", "4"])
    assert diagnose(a, lambda s: [s], lambda seeds, lines: str(sum(lines))) == "7"


def test_each_held_out_unit_gets_intervals_from_its_own_plan(seconds_run):
    """`options.intervals`: the first fit of each shared model gets, per held-out unit and
    labeled budget, a half-width per output cross-fitted over every row of its plan (a plan
    with fewer presses than folds gets none) and its coverage on the unit's test rows; the
    report tabulates them."""
    rows = json.loads((seconds_run / "metrics.json").read_text())["results"]
    banded = [r for r in rows if "interval_level" in r]
    assert banded and {r["method"].split("@")[0] for r in banded} == {"adapted:input_affine+film"}
    names = ["fx", "fy", "fz", "theta", "phi"]
    for r in banded:
        assert r["interval_level"] == 0.8 and r["budget_s"] > 0 and r["presses"] >= 3
        assert r["interval_rows"] == r["calib_samples"]
        for n in names:
            assert 0.0 <= r[f"{n}_coverage"] <= 1.0 and r[f"{n}_halfwidth"] > 0
    short = [r for r in rows if r["method"].startswith("adapted:input_affine+film@")
             and r.get("budget_s", 0) > 0 and r["presses"] < 3]
    assert all("interval_level" not in r for r in short)
    report = (seconds_run / "report.md").read_text()
    assert "## Intervals from each unit's own plan" in report and "in [0.75, 0.85]" in report


def test_the_fleet_factor_of_intervals_is_learnt_on_validation_units(seconds_run):
    """Each shared model records, per budget of calibrate's strategy, the factor its validation
    units learnt (level and folds beside it); every held-out row of that budget scales its own
    half-width by exactly that factor and scores the result; the report shows both."""
    rows = json.loads((seconds_run / "metrics.json").read_text())["results"]
    names = ["fx", "fy", "fz", "theta", "phi"]
    meta = read_header(seconds_run / "models" / "shared_input_affine-film_seed0.json", SHARED_FORMAT)["meta"]
    rec = meta["intervals"]
    assert rec["level"] == 0.8 and rec["folds"] == 3 and rec["fleet_factor_by_budget"]
    checked = 0
    for budget, factor in rec["fleet_factor_by_budget"].items():
        assert list(factor) == names and all(0 < f < math.inf for f in factor.values())
        for r in rows:
            if r["method"] == "adapted:input_affine+film@spread" and r["budget_s"] == float(budget) \
                    and "interval_level" in r and r["seed"] == 0:
                for n in names:
                    assert r[f"{n}_fleet_halfwidth"] == pytest.approx(r[f"{n}_halfwidth"] * factor[n])
                    assert 0.0 <= r[f"{n}_fleet_coverage"] <= 1.0
                    assert r[f"{n}_typical_halfwidth"] > 0 and 0.0 <= r[f"{n}_typical_coverage"] <= 1.0
                    assert r[f"{n}_shrunk_halfwidth"] == pytest.approx(
                        math.sqrt(r[f"{n}_fleet_halfwidth"] * r[f"{n}_typical_halfwidth"]))
                checked += 1
    assert checked
    report = (seconds_run / "report.md").read_text()
    assert "own plan x fleet factor" in report and "validation units' (plan unused)" in report
    typical = {r["fx_typical_halfwidth"] for r in rows if r["method"] == "adapted:input_affine+film@spread"
               and r.get("budget_s") == 40.0 and "interval_level" in r and r["seed"] == 0}
    assert len(typical) == 1  # one width for every held-out unit: the plan unused


def test_interval_fields_cover_as_the_residuals_promise():
    """Residuals and test errors from one distribution: the 90% half-width is the normal
    quantile and about 90% of test rows fall inside; no residuals, no fields."""
    from anytip.pipelines.cross_sensor_jobs import interval_fields

    rng = np.random.default_rng(0)
    resid = rng.normal(0, [1.0, 2.0], (20_000, 2))
    target = rng.normal(0, [1.0, 2.0], (20_000, 2))
    f = interval_fields(resid, np.zeros_like(target), target, ["a", "b"], 0.9)
    assert f["a_halfwidth"] == pytest.approx(1.645, rel=0.03)
    assert f["b_halfwidth"] == pytest.approx(3.29, rel=0.03)
    assert f["a_coverage"] == pytest.approx(0.9, abs=0.01) and f["b_coverage"] == pytest.approx(0.9, abs=0.01)
    assert f["interval_rows"] == 20_000 and f["interval_test_rows"] == 20_000
    assert interval_fields(None, np.zeros((3, 2)), np.zeros((3, 2)), ["a", "b"], 0.9) == {}


def test_held_out_units_are_fitted_only_at_the_prior_validation_chose(two_protocol_registry, tmp_path,
                                                                       monkeypatch):
    """The validation units are calibrated at every prior first; the held-out units then only at
    the chosen one. The own check reuses the intervals' out-of-fold fits where the folds agree."""
    import anytip.pipelines.cross_sensor as cs
    fitted: list[list[tuple]] = []
    checked: list[int] = []
    fit_jobs, own_check_losses = cs.fit_jobs, cs.own_check_losses

    def recording_fit(*args, **kwargs):
        fitted.append([(u, b.amount, b.strategy, p) for u, b, p in args[5]])
        return fit_jobs(*args, **kwargs)

    def recording_check(shared, arrays, unlabeled, plans, *args, **kwargs):
        checked.extend(p.presses for p in plans)
        return own_check_losses(shared, arrays, unlabeled, plans, *args, **kwargs)

    monkeypatch.setattr(cs, "fit_jobs", recording_fit)
    monkeypatch.setattr(cs, "own_check_losses", recording_check)
    overrides = [*SECONDS[:-2], "options.fits=[{}]", "options.adapter_priors=[identity]",
                 "options.intervals={folds: 5, level: 0.8}"]
    out = run_experiment(SPEC, two_protocol_registry, out=tmp_path / "r", overrides=overrides, progress=False)
    seed = json.loads((out / "provenance.json").read_text())["cross_sensor"]["seed0"]
    val, test = seed["units"]["val"], seed["units"]["test"]
    chosen = seed["priors_chosen"]["input_affine+film"]
    first, second = [c for c in fitted if any(amount > 0 for _, amount, _, _ in c)]  # the adapted model
    assert {u for u, *_ in first} == set(val) and {u for u, *_ in second} == set(test)
    assert {p for _, amount, _, p in first if amount > 0} == {1.0, 100.0}
    for u, amount, strategy, p in second:
        if amount > 0:
            assert p == chosen[f"{amount:g} s {strategy}"], (u, amount, strategy, p)
    assert all(presses < 2 for presses in checked)  # every plan of 2+ presses came from the intervals
    checks = seed["own_check"]["by_shared_model"]["input_affine-film"]
    assert all(v is not None and v > 0 for v in checks["40 s spread"].values())


def test_label_free_whitening_decorrelates_from_the_unlabeled_seconds_only(two_protocol_registry, tmp_path):
    """scripts/label_free_whitening.py: a unit's unlabeled seconds come out with unit covariance (no
    correlation, unit spread), and a held-out unit's whitening never reads its test patches."""
    spec = importlib.util.spec_from_file_location("whiten", REPO / "scripts" / "label_free_whitening.py")
    whiten = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(whiten)
    opts, arrays, sd = prepared(two_protocol_registry, tmp_path, [*SECONDS[:-2], "options.fits=[{}]"])
    out = whiten.whitened(arrays, opts, 0.0, sd)
    unit = sd.split.test[0]
    x = out.pressure[sd.evals[unit].stream.unlabeled(opts.unlabeled_s)].astype(np.float64)
    np.testing.assert_allclose(np.cov(x.T, bias=True), np.eye(x.shape[1]), atol=1e-3)
    test = sd.evals[unit].test_rows
    changed = dataclasses.replace(arrays, pressure=arrays.pressure.copy())
    changed.pressure[test] *= 3.0
    again = whiten.whitened(changed, opts, 0.0, sd)
    others = np.flatnonzero(arrays.unit == arrays.units.index(unit))
    others = np.setdiff1d(others, test)
    np.testing.assert_array_equal(again.pressure[others], out.pressure[others])


def test_calibrate_follows_the_plan_strategy_the_validation_units_chose(two_protocol_registry, tmp_path):
    """With several strategies compared, the shared model records the one with the lowest
    validation loss over the labeled budgets; with one, or incomplete losses, spread."""
    from anytip.data.plans import Budget
    from anytip.pipelines.cross_sensor import by_budget, calibrate_strategy
    opts, _, _ = prepared(two_protocol_registry, tmp_path,
                          [*SECONDS, "options.plan_strategies=[spread,cover]"])
    loss = {Budget(0.0, "seconds", "spread"): 9.0, Budget(8.0, "seconds", "spread"): 0.5,
            Budget(40.0, "seconds", "spread"): 0.3, Budget(8.0, "seconds", "cover"): 0.4,
            Budget(40.0, "seconds", "cover"): 0.35}
    assert calibrate_strategy(opts, loss) == "cover"  # mean 0.375 against 0.40
    loss[Budget(40.0, "seconds", "cover")] = 0.5
    assert calibrate_strategy(opts, loss) == "spread"
    del loss[Budget(40.0, "seconds", "cover")]
    assert calibrate_strategy(opts, loss) == "spread"  # cover lacks a budget: no comparison
    assert calibrate_strategy(opts) == "spread"
    assert by_budget(loss, "cover") == {"8": 0.4}


def test_a_test_set_of_one_patch_cannot_move_coverage_and_many_patches_can():
    """`test_set_fields`: drawing a unit's test patches again moves its coverage by as much as the
    patches differ; an exactly calibrated method leaves the band only when they do."""
    from anytip.pipelines.cross_sensor_jobs import test_set_fields

    rng = np.random.default_rng(0)
    target = rng.normal(size=(400, 2))
    pred = np.zeros_like(target)
    one = test_set_fields(pred, target, np.array([1.645, 1.645]), np.zeros(400, int), ["a", "b"], 0.9, 0)
    assert one["interval_test_patches"] == 1
    assert one["a_fleet_coverage_sd"] < 1e-12 and one["a_exact_p_outside"] == 0
    spread = target * np.repeat([0.5, 2.0], 200)[:, None]  # half the patches far wider than the other
    two = test_set_fields(pred, spread, np.array([1.645, 1.645]), np.repeat(np.arange(4), 100), ["a", "b"],
                          0.9, 0)
    assert two["interval_test_patches"] == 4
    assert two["a_fleet_coverage_sd"] > 0.05 and two["a_exact_p_outside"] > 0.2


def test_a_run_recorded_before_its_validation_losses_compares_and_pools_as_it_reports(cross_run, tmp_path):
    """A run whose provenance predates recorded validation losses has them in its shared models'
    metadata: `anytip compare` chooses from those and `anytip report --out` pools them, as its own
    report does."""
    from anytip.runner import compare_runs, pool_runs

    old = tmp_path / "old"
    shutil.copytree(cross_run, old)
    prov = json.loads((old / "provenance.json").read_text())
    recorded = {k: v.pop("val_loss") for k, v in prov["cross_sensor"].items()}
    (old / "provenance.json").write_text(json.dumps(prov))
    compare_runs([("old", [old], None), ("recorded", [cross_run], None)], tmp_path / "cmp")
    lines = json.loads((tmp_path / "cmp" / "comparison.json").read_text())["lines"]
    assert lines["old"] and lines["old"] == lines["recorded"]
    moved = tmp_path / "moved"  # the same units under other seeds, so the two pool
    shutil.copytree(cross_run, moved)
    rows = json.loads((moved / "metrics.json").read_text())
    for r in rows["results"]:
        r["seed"] += 10
    (moved / "metrics.json").write_text(json.dumps(rows))
    pool_runs([old, moved], tmp_path / "pooled")
    pooled = json.loads((tmp_path / "pooled" / "provenance.json").read_text())["cross_sensor"]
    assert {k.split("/")[1]: v["val_loss"] for k, v in pooled.items() if k.startswith("old/")} == recorded


def test_a_designed_plan_no_run_holds_is_named():
    """The designed calibrations a spec's `designed` budgets read but no run holds: each budget's
    `plan<B x designed_scale>`, once (the run then says that budget has no designed rows)."""
    from types import SimpleNamespace

    from anytip.pipelines.cross_sensor_jobs import missing_designs
    from anytip.pipelines.cross_sensor_options import Options
    arrays = SimpleNamespace(runs=[SimpleNamespace(protocol=p) for p in ("full", "plan120", "plan150")])
    opts = dict(budget_unit="seconds", budgets=[0, 120, 600], plan_strategies=["cover", "designed"])
    assert missing_designs(arrays, Options(**opts)) == ["plan600"]
    assert missing_designs(arrays, Options(**opts, designed_scale=1.25)) == ["plan750"]
    assert missing_designs(arrays, Options(**{**opts, "plan_strategies": ["cover"]})) == []


def test_the_benchmarks_designed_plan_reads_the_scaled_design_outside_the_test_patches(tmp_path):
    """`designed` at 30 s with `designed_scale` 1.5: every unit's plan comes from its plan45 runs alone,
    in whole presses within 30 s and outside its test patches; plan30 is never read."""
    from anytip.pipelines.cross_sensor import plan_of
    from anytip.pipelines.cross_sensor_jobs import missing_designs
    from anytip.pipelines.cross_sensor_options import budget_list

    registry = Registry(tmp_path / "r")
    simulate_into(registry, FleetConfig(), 6, seed=5, protocols=("short", "plan30", "plan45"))
    overrides = [*SECONDS[:3], "options.budget_unit=seconds", "options.budgets=[0,30]",
                 "options.plan_strategies=[designed]", "options.designed_scale=1.5",
                 "options.calibration_protocol=null", "splits.n_val_units=1", "splits.n_test_units=2",
                 "data.protocol=[short,plan30,plan45]"]
    opts, arrays, sd = prepared(registry, tmp_path, overrides)
    assert missing_designs(arrays, opts) == []
    (budget,) = [b for b in budget_list(opts) if b.amount > 0]
    for unit, ev in sd.evals.items():
        plan = plan_of(sd, unit, budget, opts, 0)
        assert len(plan.rows) and 0 < plan.calib_seconds <= 30.0
        assert {arrays.runs[k].protocol for k in np.unique(arrays.run[plan.rows])} == {"plan45"}
        assert set(arrays.patch[ev.test_rows]).isdisjoint(arrays.patch[plan.rows])
        assert not np.isin(plan.rows, ev.test_rows).any()
