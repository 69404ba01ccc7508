"""Two worker processes share one study in a real PostgreSQL server started on loopback.

`make test` installs PostgreSQL from Debian packages as root (scripts/system-deps.sh); the
test skips, saying why, where the server binaries or the driver are missing.
"""

import glob
import os
import shutil
import socket
import subprocess
import tempfile
from pathlib import Path

import optuna
import pytest

from anytip.runner import run_experiment

REPO = Path(__file__).resolve().parents[1]
BIN = sorted(glob.glob("/usr/lib/postgresql/*/bin"))
TINY = ["data.protocol=short", "training.epochs=1", "options.n_search_units=3", "options.n_test_units=3",
        "options.widths=[8,16,32,64]", "options.batch_sizes=[256]", "options.n_trials=4", "options.workers=2"]


def _missing() -> str | None:
    if not BIN:
        return "PostgreSQL server binaries are not installed (Debian package postgresql)"
    try:
        import psycopg2  # noqa: F401
    except ImportError:
        return "psycopg2 is not installed (psycopg2-binary is in the dev extras)"
    return None


def _as_server_user(cmd: list[str]) -> list[str]:
    """PostgreSQL refuses to run as root: run it as the `postgres` user there."""
    return ["runuser", "-u", "postgres", "--", *cmd] if os.geteuid() == 0 else cmd


@pytest.fixture
def postgres_url():
    root = Path(tempfile.mkdtemp(prefix="anytip-pg-", dir="/tmp"))
    os.chmod(root, 0o777)
    if os.geteuid() == 0:
        shutil.chown(root, "postgres")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    bin_dir, data = BIN[-1], root / "data"
    run = lambda *cmd: subprocess.run(_as_server_user(list(cmd)), check=True, capture_output=True)  # noqa: E731
    run(f"{bin_dir}/initdb", "-D", str(data), "-A", "trust", "-U", "postgres")
    run(f"{bin_dir}/pg_ctl", "-D", str(data), "-w", "-l", str(root / "log"), "-o",
        f"-p {port} -k {root} -c listen_addresses=127.0.0.1", "start")
    try:
        run(f"{bin_dir}/createdb", "-h", "127.0.0.1", "-p", str(port), "-U", "postgres", "anytip")
        yield f"postgresql://postgres@127.0.0.1:{port}/anytip"  # the installed driver is chosen
    finally:
        run(f"{bin_dir}/pg_ctl", "-D", str(data), "-m", "fast", "stop")
        shutil.rmtree(root, ignore_errors=True)


@pytest.mark.skipif(_missing() is not None, reason=str(_missing()))
def test_two_workers_share_a_postgresql_study(small_registry, tmp_path, postgres_url):
    import json

    run = run_experiment(REPO / "experiments" / "search.yaml", small_registry, out=tmp_path / "pg",
                         overrides=[*TINY, f"options.storage={postgres_url}"], progress=False)
    prov = json.loads((run / "provenance.json").read_text())["search"]
    assert prov["storage"] == postgres_url and prov["workers"] == 2
    assert not (run / "study.db").exists()
    from anytip.search.study import SearchOptions, rdb_storage

    study = optuna.load_study(study_name="search", storage=rdb_storage(postgres_url, SearchOptions()))
    finished = [t for t in study.trials if t.state in (optuna.trial.TrialState.COMPLETE,
                                                       optuna.trial.TrialState.PRUNED)]
    assert len(finished) == 4
