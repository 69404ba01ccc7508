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
