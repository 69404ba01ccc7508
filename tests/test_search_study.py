"""The architecture search on a tiny fleet: rows and report, the budget as constraints,
processes sharing one study, and a killed study that resumes."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import optuna
import pytest

from anytip.errors import AnytipError
from anytip.runner import run_experiment
from anytip.search.budget import load_budget

REPO = Path(__file__).resolve().parents[1]
SPEC = REPO / "experiments" / "search.yaml"
TINY = ["data.protocol=short", "training.epochs=1", "options.n_search_units=3", "options.n_test_units=3",
        "options.widths=[8,16,32,64]", "options.batch_sizes=[256]"]


def trials(run: Path) -> list[optuna.trial.FrozenTrial]:
    study = optuna.load_study(study_name="search", storage=f"sqlite:///{run / 'study.db'}")
    return study.trials


def running(run: Path) -> bool:
    """Whether the study has a running trial (reading the database only once it is there)."""
    import sqlite3

    try:
        with sqlite3.connect(f"file:{run / 'study.db'}?mode=ro", uri=True) as db:
            return bool(db.execute("SELECT count(*) FROM trials WHERE state = 'RUNNING'").fetchone()[0])
    except sqlite3.Error:
        return False


def test_search_rows_report_and_budget(small_registry, tmp_path):
    run = run_experiment(SPEC, small_registry, out=tmp_path / "s", overrides=[*TINY, "options.n_trials=4"],
                         progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    prov = json.loads((run / "provenance.json").read_text())["search"]
    assert {r["method"] for r in rows} >= {"paper_mlp"}
    assert {r["unit"] for r in rows} == set(prov["test_units"])
    assert set(prov["test_units"]).isdisjoint(prov["search_units"])
    for r in rows:
        assert {"params", "macs", "flash_bytes", "ram_bytes", "pareto"} <= r.keys()
    budget = load_budget("stm32f334")
    for t in trials(run):
        if t.state == optuna.trial.TrialState.COMPLETE:
            assert t.user_attrs["flash_bytes"] <= budget.flash_bytes_max
    assert "Pareto" in (run / "report.md").read_text() and (run / "pareto.png").is_file()


def test_two_workers_share_one_study(small_registry, tmp_path):
    run = run_experiment(SPEC, small_registry, out=tmp_path / "w",
                         overrides=[*TINY, "options.n_trials=4", "options.workers=2"], progress=False)
    done = [t for t in trials(run) if t.state in (optuna.trial.TrialState.COMPLETE,
                                                  optuna.trial.TrialState.PRUNED)]
    assert len(done) == 4
    assert json.loads((run / "provenance.json").read_text())["search"]["workers"] == 2


def test_a_killed_study_resumes(small_registry, tmp_path):
    out = tmp_path / "k"
    sets = [*TINY, "options.n_trials=3", "options.heartbeat_s=1", "training.epochs=40"]
    args = [sys.executable, "-m", "anytip.cli", "run", str(SPEC), "--registry", str(small_registry.root),
            "--out", str(out), *sum((["--set", s] for s in sets), [])]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    deadline = time.time() + 60
    while time.time() < deadline and not running(out):
        time.sleep(0.3)
    time.sleep(1.5)  # mid-trial, after its first heartbeats
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    assert any(t.state == optuna.trial.TrialState.RUNNING for t in trials(out))
    time.sleep(2.5)  # past the grace period: the killed trial's heartbeat is stale
    run_experiment(SPEC, small_registry, out=out, overrides=[*TINY, "options.n_trials=3",
                                                             "options.heartbeat_s=1"], progress=False)
    states = [t.state for t in trials(out)]
    assert optuna.trial.TrialState.FAIL in states and optuna.trial.TrialState.RUNNING not in states
    finished = [s for s in states if s in (optuna.trial.TrialState.COMPLETE, optuna.trial.TrialState.PRUNED)]
    assert len(finished) == 3


def test_activation_and_feature_dimensions(small_registry, tmp_path):
    run = run_experiment(SPEC, small_registry, out=tmp_path / "a", progress=False, overrides=[
        *TINY, "options.n_trials=3", "options.activations=[leaky_relu,hardswish]",
        "options.features=[neighbour_diffs]"])
    done = [t for t in trials(run) if t.state == optuna.trial.TrialState.COMPLETE]
    assert done and all(t.params["activation"] in ("leaky_relu", "hardswish") for t in done)
    assert all(t.params["features"] == "neighbour_diffs" for t in done)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    # the paper's ReLU MLP is outside the space; the best member is also scored with raw inputs and ReLU
    assert rows and {r["method"] for r in rows} == {"search", "ablation"}
    for r in rows:
        assert r["sizes"][0] == 8 and r["force_rmse_n"] > 0
        assert r["features"] == "neighbour_diffs" or r["method"] == "ablation"
    ablated = {(r["trial"], r["activation"], r["features"]) for r in rows if r["method"] == "ablation"}
    assert len(ablated) == 2 and {a[1:] for a in ablated} >= {("relu", "neighbour_diffs")}


def test_shared_family_scores_only_search_units(small_registry, tmp_path):
    run = run_experiment(SPEC, small_registry, out=tmp_path / "sh", progress=False, overrides=[
        *TINY, "options.family=shared", "options.n_search_units=2", "options.n_test_units=2",
        "options.n_trials=3", "options.calib_samples=200", "options.adapter_steps=10",
        "options.max_train_rows=1000", "options.adapters=[input_diag,input_affine+film]"])
    prov = json.loads((run / "provenance.json").read_text())["search"]
    search, test, train = set(prov["search_units"]), set(prov["test_units"]), set(prov["train_units"])
    assert prov["family"] == "shared" and len(train) == 4
    assert search.isdisjoint(test) and train.isdisjoint(search | test)
    done = [t for t in trials(run) if t.state == optuna.trial.TrialState.COMPLETE]
    scored = {u for t in done for u in t.user_attrs["units"]}
    assert scored == search  # the objective never touched a test (or training) unit
    assert all(t.params["adapter"] in ("input_diag", "input_affine+film") for t in done)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    assert {r["unit"] for r in rows} == test and "paper_mlp" in {r["method"] for r in rows}
    for r in rows:
        assert r["calib_samples"] <= 200 and r["family"] == "shared"
        assert {"adapter", "activation", "features", "pareto", "macs", "flash_bytes", "ram_bytes"} <= r.keys()
    paper = next(r for r in rows if r["method"] == "paper_mlp")
    assert paper["adapter"] == "input_diag" and paper["activation"] == "relu"
    assert "Family `shared`" in (run / "report.md").read_text()


@pytest.mark.parametrize(("override", "message"), [
    ("options.activations=[relu,tanh]", r"options.*activations.*'tanh'.*need libm"),
    ("options.features=[raw,pca]", r"options.*features.*unknown input features \['pca'\]"),
    ("options.family=pooled", r"options.*family"),
    ("options.adapters=[input_foo]", r"options.*adapters.*unknown part"),
])
def test_bad_options_name_the_key(small_registry, tmp_path, override, message):
    with pytest.raises(AnytipError, match=message):
        run_experiment(SPEC, small_registry, out=tmp_path / "bad", overrides=[*TINY, override],
                       progress=False)


@pytest.mark.parametrize("url, message", [
    ("not a url", "is not a database URL"),
    ("journal:///tmp/study.log", "no database driver"),
    ("sqlite:////nonexistent-dir/study.db", "cannot open the database"),
])
def test_bad_storage_url_names_the_option(url, message):
    from anytip.search.study import SearchOptions, rdb_storage

    with pytest.raises(AnytipError, match=f"options.storage.*{message}"):
        rdb_storage(url, SearchOptions())


def test_storage_error_hides_the_password():
    from anytip.search.study import SearchOptions, rdb_storage

    with pytest.raises(AnytipError) as err:
        rdb_storage("postgresql://user:secret@127.0.0.1:1/db", SearchOptions())
    assert "secret" not in str(err.value) and "***" in str(err.value)
