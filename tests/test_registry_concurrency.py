"""The registry under several processes: concurrent imports, crashed writers, scratch cleanup."""

from __future__ import annotations

import sqlite3
import subprocess
import sys
import threading
import time
from contextlib import closing
from pathlib import Path

import pytest

from anytip.data import catalog
from anytip.data.catalog import make_run_id
from anytip.data.registry import Registry
from anytip.data.runfile import write_run
from anytip.data.staging import Staging
from run_factory import make_run

# Waits for a "go" file so that both processes stage and commit at the same moment.
IMPORTER = """
import os, sys, time
from anytip.data.registry import Registry
root, go, paths = sys.argv[1], sys.argv[2], sys.argv[3:]
while not os.path.exists(go):
    time.sleep(0.005)
report = Registry(root).import_paths(paths)
print(len(report.added), len(report.unchanged))
"""

# Dies (as from SIGKILL or power loss) after payloads are renamed into runs/ but before commit.
CRASHER = """
import os, sys
from anytip.data import catalog
from anytip.data.registry import Registry
catalog.insert = lambda conn, record: os._exit(9)
Registry(sys.argv[1]).import_paths(sys.argv[2:])
"""


@pytest.fixture(scope="module")
def run_files(tmp_path_factory) -> list[Path]:
    folder = tmp_path_factory.mktemp("runs")
    runs = [make_run(f"FT-{i % 6:04d}", -45.0 * (i % 3), f"2024-05-01T12:00:{i:02d}Z", n=3000, seed=i)
            for i in range(24)]
    return [write_run(r, folder / f"run{i:02d}.h5") for i, r in enumerate(runs)]


def import_in_processes(root: Path, path_sets: list[list[Path]], tmp_path: Path) -> list[tuple[int, int]]:
    go = tmp_path / "go"
    procs = [subprocess.Popen([sys.executable, "-c", IMPORTER, str(root), str(go), *map(str, paths)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for paths in path_sets]
    time.sleep(0.3)
    go.touch()
    results = []
    for proc in procs:
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
        added, unchanged = map(int, out.split())
        results.append((added, unchanged))
    return results


def expected_hash(paths: list[Path]) -> str:
    from anytip.data.runfile import read_run

    runs = [read_run(p) for p in paths]
    return catalog.hash_pairs((make_run_id(r), r.content_hash()) for r in runs)


def test_two_processes_import_overlapping_sets(tmp_path, run_files):
    root = tmp_path / "reg"  # created by the racing processes themselves
    a, b = run_files[:16], run_files[8:]
    (added_a, same_a), (added_b, same_b) = import_in_processes(root, [a, b], tmp_path)
    assert added_a + same_a == 16 and added_b + same_b == 16
    assert added_a + added_b == 24
    reg = Registry(root)
    assert len(reg.list_runs()) == 24
    assert reg.content_hash() == expected_hash(run_files)
    assert reg.verify().ok
    assert list((root / "tmp").iterdir()) == []


def test_two_processes_import_the_same_set(tmp_path, run_files):
    root = tmp_path / "reg"
    Registry(root).import_paths(run_files[:2])
    results = import_in_processes(root, [run_files[:12], run_files[:12]], tmp_path)
    assert sum(added for added, _ in results) == 10
    reg = Registry(root)
    assert reg.content_hash() == expected_hash(run_files[:12]) and reg.verify().ok


def test_crashed_writer_leaves_catalog_unchanged(tmp_path, run_files):
    reg = Registry(tmp_path / "reg")
    reg.import_paths(run_files[:3])
    rows, registry_hash = reg.list_runs(), reg.content_hash()
    proc = subprocess.run([sys.executable, "-c", CRASHER, str(reg.root), *map(str, run_files[3:6])],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 9, proc.stderr
    assert reg.list_runs() == rows and reg.content_hash() == registry_hash
    report = reg.verify()
    assert len(report.orphans) == 3 and not (report.missing or report.corrupt or report.bad_rows)
    assert list((reg.root / "tmp").iterdir())  # the dead writer's scratch space
    assert len(reg.import_paths(run_files[3:6]).added) == 3
    assert reg.verify().ok and list((reg.root / "tmp").iterdir()) == []


def test_dead_scratch_is_cleaned_and_live_scratch_kept(tmp_path):
    reg = Registry(tmp_path / "reg")
    tmp = reg.root / "tmp"
    (tmp / "123-dead").mkdir(parents=True)
    (tmp / "123-dead" / "0.h5").write_bytes(b"half a file")
    (tmp / "123-dead.lock").touch()
    (tmp / "no-lock-dir").mkdir()
    with Staging(tmp) as live:
        (live.dir / "0.h5").write_bytes(b"being written")
        reg.add_runs([make_run()])
        assert (live.dir / "0.h5").read_bytes() == b"being written" and live.lock_path.exists()
        assert sorted(p.name for p in tmp.iterdir()) == sorted([live.dir.name, live.lock_path.name])
    assert list(tmp.iterdir()) == [] and reg.verify().ok


def test_writer_waits_for_a_held_write_lock_and_readers_do_not(tmp_path):
    reg = Registry(tmp_path / "reg")
    reg.add_runs([make_run("FT-1")])
    holder = sqlite3.connect(reg.db_path, isolation_level=None, check_same_thread=False)
    holder.execute("BEGIN IMMEDIATE")
    started = time.monotonic()
    assert [r.unit for r in reg.list_runs()] == ["FT-1"]  # WAL: reading is not blocked
    assert time.monotonic() - started < 0.4
    threading.Timer(0.5, lambda: holder.execute("COMMIT")).start()
    reg.add_runs([make_run("FT-2")])
    assert time.monotonic() - started >= 0.5
    holder.close()
    assert reg.units() == ["FT-1", "FT-2"]


OPENER = """
import os, sys, time
from anytip.data.registry import Registry
while not os.path.exists(sys.argv[2]):
    time.sleep(0.001)
Registry(sys.argv[1])
"""


def test_many_processes_create_one_registry_at_once(tmp_path):
    # The first connections race to create the catalog and switch it to WAL.
    for attempt in range(3):
        root, go = tmp_path / f"reg{attempt}", tmp_path / f"go{attempt}"
        procs = [subprocess.Popen([sys.executable, "-c", OPENER, str(root), str(go)],
                                  stderr=subprocess.PIPE, text=True) for _ in range(6)]
        time.sleep(1.0)
        go.touch()
        for proc in procs:
            _, err = proc.communicate(timeout=120)
            assert proc.returncode == 0, err
        with closing(catalog.connect(root / "catalog.sqlite")) as conn:
            assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
            assert conn.execute("PRAGMA user_version").fetchone()[0] == catalog.SCHEMA_VERSION
