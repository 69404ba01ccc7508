"""`anytip report RUN RUN ... --out DIR`: several finished runs of one cross_sensor benchmark (unit
folds run apart) pooled into one report, from the runs' own files alone."""

from __future__ import annotations

from pathlib import Path

import pytest

from anytip.cli import main
from anytip.config import load_spec, public_config
from anytip.errors import AnytipError
from anytip.rundir import read_json, write_config, write_json, write_metrics
from anytip.runner import compare_runs, pool_runs

SPEC = Path(__file__).resolve().parents[1] / "experiments" / "cross_sensor_response_start.yaml"
TARGETS = {"force": {"unit": "N", "components": ["fx", "fy", "fz"]},
           "angles": {"unit": "rad", "components": ["theta", "phi"]}}


def row(method: str, unit: str, seed: int, force: float, budget: float | None = 120.0) -> dict:
    r = {"method": method, "unit": unit, "seed": seed, "calib_samples": 100, "n_train_units": 2,
         "calib_seconds": budget, "force_rmse_n": force, "angle_rmse_rad": force / 10}
    return r if budget is None else {**r, "budget_s": budget}


def finished_run(path: Path, seed: int, held_out: dict[str, tuple[float, float, float]],
                 val: dict[str, float], overrides: list[str] | None = None,
                 sensor: str = "fingertip-8baro-r10", budget: float = 120.0) -> Path:
    """A run directory as a cross_sensor run leaves it: held_out maps each held-out unit to its
    per_unit, `a@cover` and `b@cover` force RMSE at `budget` s; `val` each method's validation loss."""
    path.mkdir(parents=True)
    write_config(path, public_config(load_spec(SPEC, [f"seeds=[{seed}]", *(overrides or [])])))
    methods = ("per_unit", "a@cover", "b@cover")
    rows = [row(m, u, seed, f, None if m == "per_unit" else budget)
            for u, forces in held_out.items() for m, f in zip(methods, forces, strict=True)]
    write_metrics(path, rows)
    split = {"train": ["T1", "T2"], "val": ["V1"], "test": sorted(held_out)}
    write_json(path / "provenance.json", {
        "sensor_model": sensor, "targets": TARGETS, "units": ["T1", "T2", "V1", *sorted(held_out)],
        "cross_sensor": {f"seed{seed}": {"units": split,
                                         "val_loss": {m: {f"{budget:g}": v} for m, v in val.items()}}}})
    return path


def folds(tmp_path: Path) -> list[Path]:
    """Two folds: the validation units prefer `a` in fold 0 and `b` in fold 1, `a` on average."""
    return [finished_run(tmp_path / "fold0", 0, {"U1": (1.0, 1.2, 0.9), "U2": (2.0, 2.0, 1.8)},
                         {"a@cover": 0.10, "b@cover": 0.13}),
            finished_run(tmp_path / "fold1", 1, {"U3": (1.0, 1.4, 1.0), "U4": (1.0, 1.0, 1.0)},
                         {"a@cover": 0.12, "b@cover": 0.11})]


def test_a_pooled_report_scores_every_fold_s_units_with_the_mean_validation_choice(tmp_path):
    report = pool_runs(folds(tmp_path), tmp_path / "pooled")
    text = report.read_text()
    # a: 0.11 mean validation loss against b's 0.12; its ratios 1.2, 1.0, 1.4, 1.0 over four units
    assert "`a@cover` @ 120 | 1.15x [" in text
    assert "| 4 | 4 |" in text  # four distinct units, four rows
    assert "fold0" in text and "fold1" in text and "same spec" in text
    rows = read_json(tmp_path / "pooled" / "metrics.json")["results"]
    assert sorted({r["pooled_run"] for r in rows}) == [0, 1] and len(rows) == 12
    pooled = read_json(tmp_path / "pooled" / "provenance.json")
    assert set(pooled["cross_sensor"]) == {"fold0/seed0", "fold1/seed1"}
    assert load_spec(tmp_path / "pooled" / "config.yaml").seeds == [0, 1]
    main(["report", str(tmp_path / "pooled")])  # a pooled directory is a run directory: rewritten alike
    assert (tmp_path / "pooled" / "report.md").read_text() == text


def test_specs_that_differ_are_listed(tmp_path):
    runs = [*folds(tmp_path),
            finished_run(tmp_path / "fold2", 2, {"U5": (1.0, 1.1, 1.2)}, {"a@cover": 0.1, "b@cover": 0.2},
                         ["options.response.inverse_epochs=60"])]
    text = pool_runs(runs, tmp_path / "pooled").read_text()
    assert "`options.response.inverse_epochs`: `60`" in text


def test_a_unit_scored_in_two_runs_is_refused(tmp_path):
    a, _ = folds(tmp_path)
    again = finished_run(tmp_path / "rescored", 0, {"U1": (1.0, 1.1, 1.0)}, {"a@cover": 0.1, "b@cover": 0.2})
    with pytest.raises(AnytipError, match="unit U1, seed 0 is scored in both"):
        pool_runs([a, again], tmp_path / "pooled")
    assert not (tmp_path / "pooled").exists()


def test_a_run_and_its_rescoring_at_other_budgets_pool_into_one_curve(tmp_path, capsys):
    a, _ = folds(tmp_path)
    at600 = finished_run(tmp_path / "at600", 0, {"U1": (1.0, 0.8, 0.9), "U2": (2.0, 1.8, 1.8)},
                         {"a@cover": 0.05, "b@cover": 0.06}, budget=600.0)
    assert main(["compare", f"a={a},{at600}#a@cover", f"b={a},{at600}#b@cover",
                 "--out", str(tmp_path / "cmp")]) == 0, capsys.readouterr().err
    text = (tmp_path / "cmp" / "report.md").read_text()
    assert "| a | 120 | `a@cover` | 120.0 | 1.10x [1.00, 1.20]" in text  # U1 1.2, U2 1.0
    assert "| a | 600 | `a@cover` | 600.0 | 0.85x [0.80, 0.90]" in text  # U1 0.8, U2 0.9
    rows = read_json(pool_runs([a, at600], tmp_path / "pooled").parent / "metrics.json")["results"]
    assert len([r for r in rows if r["method"] == "per_unit"]) == 2  # each unit's reference once
    assert len(rows) == 2 + 4 + 4


def test_a_named_method_pools_where_the_runs_other_methods_score_the_same_budget(tmp_path):
    a, _ = folds(tmp_path)
    both = finished_run(tmp_path / "both", 0, {"U1": (1.0, 0.8, 0.9)}, {"a@cover": 0.05}, budget=600.0)
    rows = read_json(both / "metrics.json")["results"]
    write_metrics(both, [r if r["method"] != "b@cover" else {**r, "budget_s": 120.0} for r in rows])
    compare_runs([("a", [a, both], "a@cover"), ("fold0", [a], None)], tmp_path / "cmp")
    assert "| a | 600 | `a@cover` |" in (tmp_path / "cmp" / "report.md").read_text()
    with pytest.raises(AnytipError, match="b@cover at budget 120 in each"):
        compare_runs([("b", [a, both], None), ("fold0", [a], None)], tmp_path / "cmp2")


def test_runs_of_one_unit_with_references_that_differ_are_refused(tmp_path):
    a, _ = folds(tmp_path)
    other_reference = finished_run(tmp_path / "at600", 0, {"U1": (1.1, 0.8, 0.9)}, {"a@cover": 0.05},
                                   budget=600.0)
    with pytest.raises(AnytipError, match=r"unit U1, seed 0 is scored in both .* references that differ "
                                          r"\(per_unit angle_rmse_rad: 0.1 against 0.11"):
        pool_runs([a, other_reference], tmp_path / "pooled")
    assert not (tmp_path / "pooled").exists()


def test_other_sensor_models_and_pipelines_are_refused(tmp_path):
    a, _ = folds(tmp_path)
    other = finished_run(tmp_path / "other", 3, {"U9": (1.0, 1.0, 1.0)}, {"a@cover": 0.1}, sensor="dome-6")
    with pytest.raises(AnytipError, match="its sensor_model 'dome-6' differs"):
        pool_runs([a, other], tmp_path / "pooled")
    baseline = tmp_path / "baseline"
    baseline.mkdir()
    write_config(baseline, public_config(load_spec(SPEC.parent / "baseline.yaml")))
    write_metrics(baseline, [row("per_unit", "U1", 0, 1.0, None)])
    write_json(baseline / "provenance.json", {"sensor_model": "fingertip-8baro-r10", "targets": TARGETS})
    with pytest.raises(AnytipError, match="pipeline 'baseline' cannot be pooled"):
        pool_runs([baseline, a], tmp_path / "pooled")


def test_the_command_line_names_what_is_wrong(tmp_path, capsys):
    a, b = folds(tmp_path)
    assert main(["report", str(a), str(b)]) == 2
    assert "give --out DIR" in capsys.readouterr().err
    assert main(["report", str(a), str(tmp_path / "nowhere"), "--out", str(tmp_path / "p")]) == 2
    assert "nowhere: not a finished run directory (no config.yaml)" in capsys.readouterr().err
    (b / "metrics.json").write_text("[1, 2]")
    assert main(["report", str(a), str(b), "--out", str(tmp_path / "p")]) == 2
    assert "metrics.json: no 'results' list of rows" in capsys.readouterr().err
    assert main(["report", str(a), "--out", str(tmp_path / "p")]) == 2
    assert "at least two run directories" in capsys.readouterr().err


def test_a_finished_pool_is_not_overwritten_without_force(tmp_path):
    runs = folds(tmp_path)
    pool_runs(runs, tmp_path / "pooled")
    with pytest.raises(AnytipError, match="already holds a finished run"):
        pool_runs(runs, tmp_path / "pooled")
    pool_runs(runs, tmp_path / "pooled", force=True)


def test_a_comparison_shows_each_run_s_own_validation_choice(tmp_path):
    a, b = folds(tmp_path)  # fold 0's validation units choose a, fold 1's b
    out = ["--out", str(tmp_path / "cmp"), "--title", "By severity"]
    assert main(["compare", f"gentle={a}", f"severe={b}", *out]) == 0
    text = (tmp_path / "cmp" / "report.md").read_text()
    assert text.startswith("# By severity")
    assert "| gentle | 120 | `a@cover` | 120.0 | 1.10x [1.00, 1.20]" in text  # U1 1.2, U2 1.0
    assert "| severe | 120 | `b@cover` | 120.0 | 1.00x [1.00, 1.00]" in text  # U3 1.0, U4 1.0
    assert (tmp_path / "cmp" / "ratio_by_run.png").stat().st_size > 0
    lines = read_json(tmp_path / "cmp" / "comparison.json")["lines"]
    assert [ln["method"] for ln in lines["severe"]] == ["b@cover"]


def test_a_comparison_refuses_unlabelled_runs_and_runs_without_a_validation_choice(tmp_path, capsys):
    a, b = folds(tmp_path)
    assert main(["compare", str(a), f"b={b}", "--out", str(tmp_path / "cmp")]) == 2
    assert "give each entry as LABEL=RUN_DIR" in capsys.readouterr().err
    assert main(["compare", f"x={a}", f"x={b}", "--out", str(tmp_path / "cmp")]) == 2
    assert "labels must be distinct" in capsys.readouterr().err
    prov = read_json(b / "provenance.json")
    del prov["cross_sensor"]["seed1"]["val_loss"]
    write_json(b / "provenance.json", prov)
    assert main(["compare", f"a={a}", f"b={b}", "--out", str(tmp_path / "cmp")]) == 2
    assert "no validation losses recorded" in capsys.readouterr().err
    assert not (tmp_path / "cmp").exists()


def test_a_comparison_shows_a_named_method_and_refuses_one_the_run_lacks(tmp_path, capsys):
    a, b = folds(tmp_path)
    assert main(["compare", f"all={a}", f"without b={a}#a@cover", f"fold1={b}#a@cover",
                 "--out", str(tmp_path / "cmp")]) == 0
    text = (tmp_path / "cmp" / "report.md").read_text()
    assert "| without b | 120 | `a@cover` | 120.0 | 1.10x [1.00, 1.20]" in text
    assert "| fold1 | 120 | `a@cover` | 120.0 | 1.20x [1.00, 1.40]" in text  # not fold 1's choice, b
    assert main(["compare", f"x={a}", f"y={b}#c@cover", "--out", str(tmp_path / "cmp2")]) == 2
    assert "no rows of method 'c@cover'; it holds a@cover, b@cover" in capsys.readouterr().err


def test_a_comparison_entry_pools_folds_and_may_hold_the_same_units_as_another(tmp_path):
    a, b = folds(tmp_path)
    assert main(["compare", f"pooled={a},{b}", f"fold0={a}", "--out", str(tmp_path / "cmp")]) == 0
    text = (tmp_path / "cmp" / "report.md").read_text()
    assert "| pooled | 120 | `a@cover` | 120.0 | 1.15x [" in text and "| 4 |" in text  # mean choice: a
    again = finished_run(tmp_path / "rescored", 0, {"U1": (1.0, 1.1, 1.0)}, {"a@cover": 0.1, "b@cover": 0.2})
    with pytest.raises(AnytipError, match="unit U1, seed 0 is scored in both"):
        compare_runs([("x", [a, again], None), ("y", [b], None)], tmp_path / "cmp2")


def test_no_run_read_is_overwritten_and_a_row_without_its_keys_is_named(tmp_path, capsys):
    a, b = folds(tmp_path)
    before = (a / "metrics.json").read_text()
    into_a_run = (["report", str(a), str(b), "--out", str(a)],
                  ["compare", f"x={a}", f"y={b}", "--out", str(b)])
    for argv in into_a_run:
        assert main(argv) == 2
        assert "is one of the runs read" in capsys.readouterr().err
    other = finished_run(tmp_path / "other", 5, {"U7": (1.0, 1.0, 1.0)}, {"a@cover": 0.1, "b@cover": 0.2})
    report = (other / "report.md").exists()
    assert main(["compare", f"x={a}", f"y={b}", "--out", str(other)]) == 2
    assert "holds a finished run" in capsys.readouterr().err
    assert (other / "report.md").exists() == report and (a / "metrics.json").read_text() == before
    rows = read_json(b / "metrics.json")
    del rows["results"][0]["seed"]
    write_json(b / "metrics.json", rows)
    assert main(["report", str(a), str(b), "--out", str(tmp_path / "p")]) == 2
    assert "metrics.json: a result row lacks 'seed'" in capsys.readouterr().err
