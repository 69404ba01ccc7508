"""The registry: catalog rows, run ids, import/export, verify, remove, hashes, safety."""

from __future__ import annotations

import json
import os
import sqlite3
from pathlib import Path

import h5py
import numpy as np
import pytest

from anytip.data import catalog
from anytip.data.catalog import RunRecord, make_run_id
from anytip.data.registry import Registry, default_registry_path
from anytip.data.runfile import read_run, write_run
from anytip.errors import AnytipError
from run_factory import make_run


@pytest.fixture
def reg(tmp_path) -> Registry:
    return Registry(tmp_path / "reg")


def snapshot(reg: Registry) -> tuple[list[RunRecord], list[str]]:
    """Catalog rows and every file under the registry root except the SQLite files."""
    files = sorted(p.relative_to(reg.root).as_posix() for p in reg.root.rglob("*")
                   if p.is_file() and not p.name.startswith("catalog.sqlite"))
    return reg.list_runs(), files


def write_files(folder: Path, runs) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    return [write_run(r, folder / f"{i:02d}.h5") for i, r in enumerate(runs)]


def test_default_registry_path(monkeypatch, tmp_path):
    monkeypatch.delenv("ANYTIP_REGISTRY", raising=False)
    assert default_registry_path() == Path("data/registry")
    monkeypatch.setenv("ANYTIP_REGISTRY", str(tmp_path / "elsewhere"))
    assert default_registry_path() == tmp_path / "elsewhere"
    assert Registry().root == tmp_path / "elsewhere"


def test_missing_registry_without_create(tmp_path):
    with pytest.raises(AnytipError, match="not a registry"):
        Registry(tmp_path / "absent", create=False)
    (tmp_path / "empty").mkdir()
    with pytest.raises(AnytipError, match="not a registry"):  # a directory is not a registry
        Registry(tmp_path / "empty", create=False)
    assert not (tmp_path / "absent").exists() and not any((tmp_path / "empty").iterdir())


@pytest.mark.parametrize(("orientation", "created", "expected"), [
    (-45, "2024-05-01T12:00:00Z", "FT-0007_o-45_20240501T120000Z"),
    (0.0, "2024-05-01T14:00:00+02:00", "FT-0007_o0_20240501T120000Z"),
    (22.5, "2024-05-01T12:00:00.250000", "FT-0007_o22.5_20240501T120000.250000Z"),
])
def test_run_id_rule(orientation, created, expected):
    assert make_run_id(make_run("FT-0007", orientation, created)) == expected


def test_run_id_needs_iso_time():
    with pytest.raises(AnytipError, match="ISO 8601"):
        make_run_id(make_run(created="yesterday"))


def test_add_runs_records_catalog_columns(reg):
    run = make_run("FT-0001", -90, n=400, protocol="full")
    (rec,) = reg.add_runs([run])
    assert rec.run_id == "FT-0001_o-90_20240501T120000Z"
    assert (rec.unit, rec.sensor_model, rec.orientation_deg, rec.source) == (
        "FT-0001", "fingertip-8baro-r10", -90.0, "simulated")
    assert (rec.rows, rec.channels, rec.duration_s, rec.protocol) == (400, 8, 2.0, "full")
    assert rec.sha256 == run.content_hash() and rec.created == run.created
    assert rec.path == "runs/FT-0001/FT-0001_o-90_20240501T120000Z.h5"
    assert reg.payload_path(rec.run_id) == reg.root / rec.path
    assert reg.list_runs() == [rec] and reg.record(rec.run_id) == rec
    assert json.loads(json.dumps(rec.to_json()))["run_id"] == rec.run_id
    assert make_run(protocol=None).extra.get("simulator") is None
    assert reg.add_runs([make_run("FT-0002")])[0].protocol is None


def test_payload_is_an_interchange_file(reg):
    (rec,) = reg.add_runs([make_run()])
    assert read_run(reg.payload_path(rec.run_id)).content_hash() == rec.sha256


def test_open_run_gives_the_same_values(reg):
    run = make_run(n=300)
    (rec,) = reg.add_runs([run])
    assert reg.open_run(rec.run_id).content_hash() == run.content_hash()
    with pytest.raises(AnytipError, match="no run"):
        reg.open_run("FT-9_o0_20240501T120000Z")


def test_same_content_twice_is_unchanged(reg, tmp_path):
    paths = write_files(tmp_path / "in", [make_run("FT-0001"), make_run("FT-0002")])
    first = reg.import_paths(paths)
    assert len(first.added) == 2 and first.unchanged == []
    before = snapshot(reg)
    again = reg.import_paths(paths)
    assert again.added == [] and again.unchanged == first.added
    assert snapshot(reg) == before


def test_duplicate_inputs_in_one_import(reg, tmp_path):
    run = make_run()
    paths = [write_run(run, tmp_path / "a.h5"), write_run(run, tmp_path / "b.h5")]
    report = reg.import_paths(paths)
    assert len(report.added) == 1 and len(report.unchanged) == 1
    assert reg.add_runs([run, run]) == [report.added[0]] * 2


def test_same_run_id_different_content_is_refused(reg, tmp_path):
    reg.import_paths([write_run(make_run(seed=1), tmp_path / "first.h5")])
    before = snapshot(reg)
    other = make_run(seed=2)
    path = write_run(other, tmp_path / "second.h5")
    with pytest.raises(AnytipError) as info:
        reg.import_paths([path])
    msg = str(info.value)
    run_id = make_run_id(other)
    assert run_id in msg and str(path) in msg and f"runs/FT-0001/{run_id}.h5" in msg
    assert other.content_hash()[:12] in msg and make_run(seed=1).content_hash()[:12] in msg
    assert snapshot(reg) == before


def test_clash_inside_one_batch_is_refused(reg):
    with pytest.raises(AnytipError, match="already taken"):
        reg.add_runs([make_run(seed=1), make_run(seed=2)], source_paths=["a.h5", "b.h5"])
    assert snapshot(reg) == ([], [])


def test_import_refuses_everything_and_lists_every_bad_file(reg, tmp_path):
    good = write_files(tmp_path / "in", [make_run(f"FT-{i}") for i in range(3)])
    not_hdf5 = tmp_path / "in" / "notes.h5"
    not_hdf5.write_text("hello")
    truncated = tmp_path / "in" / "sub" / "cut.hdf5"
    truncated.parent.mkdir()
    full = write_run(make_run("FT-9", n=3000), tmp_path / "full.h5").read_bytes()
    truncated.write_bytes(full[: len(full) // 2])
    missing = tmp_path / "nowhere.h5"
    with pytest.raises(AnytipError) as info:
        reg.import_paths([tmp_path / "in", missing])
    msg = str(info.value)
    for bad in (not_hdf5, truncated, missing):
        assert str(bad) in msg
    assert "nothing imported" in msg and not any(str(g) in msg for g in good)
    assert snapshot(reg) == ([], [])


def test_import_recurses_into_directories(reg, tmp_path):
    write_files(tmp_path / "in" / "a", [make_run("FT-1")])
    write_files(tmp_path / "in" / "b" / "c", [make_run("FT-2"), make_run("FT-3", 45)])
    (tmp_path / "in" / "README.txt").write_text("ignored")
    report = reg.import_paths([tmp_path / "in"])
    assert [r.unit for r in report.added] == ["FT-1", "FT-2", "FT-3"]


def test_explicit_file_of_unknown_kind_is_refused(reg, tmp_path):
    path = tmp_path / "run.txt"
    path.write_text("x")
    with pytest.raises(AnytipError, match="not a run file"):
        reg.import_paths([path])


def test_import_export_round_trip(reg, tmp_path):
    runs = [make_run("FT-1", o, n=500, seed=i) for i, o in enumerate((0, -45, -90))]
    paths = write_files(tmp_path / "in", runs)
    reg.import_paths(paths)
    out = reg.export("FT-1", tmp_path / "out")
    assert len(out) == 3
    hashes = {read_run(p).content_hash() for p in out}
    assert hashes == {read_run(p).content_hash() for p in paths} == {r.content_hash() for r in runs}
    (one,) = reg.export(make_run_id(runs[1]), tmp_path / "one")
    assert one.name == f"{make_run_id(runs[1])}.h5"
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".")]
    with pytest.raises(AnytipError, match="no run or unit"):
        reg.export("FT-404", tmp_path / "out")


def test_list_runs_filters_and_units(reg):
    reg.add_runs([
        make_run("FT-1", protocol="full"), make_run("FT-2", protocol="short"),
        make_run("FT-3", sensor_model="fingertip-6baro", protocol="full"),
        make_run("FT-1", -45, protocol="short"),
    ])
    assert len(reg.list_runs()) == 4
    assert {r.run_id for r in reg.list_runs(unit="FT-1")} == {
        "FT-1_o0_20240501T120000Z", "FT-1_o-45_20240501T120000Z"}
    assert [r.unit for r in reg.list_runs(protocol="full")] == ["FT-1", "FT-3"]
    assert [r.unit for r in reg.list_runs(unit="FT-1", protocol="short")] == ["FT-1"]
    assert reg.units() == ["FT-1", "FT-2", "FT-3"]
    assert reg.units(sensor_model="fingertip-6baro") == ["FT-3"]
    assert reg.list_runs(sensor_model="nope") == []


def test_content_hash_is_order_independent(tmp_path):
    runs = [make_run(f"FT-{i}", seed=i) for i in range(4)]
    a, b = Registry(tmp_path / "a"), Registry(tmp_path / "b")
    a.add_runs(runs)
    for run in reversed(runs):
        b.add_runs([run])
    assert a.content_hash() == b.content_hash()
    ids = [make_run_id(r) for r in runs[:2]]
    assert a.content_hash(ids) == a.content_hash(list(reversed(ids))) != a.content_hash()
    assert a.content_hash(ids) == catalog.hash_pairs((make_run_id(r), r.content_hash()) for r in runs[:2])
    b.remove("FT-3")
    assert a.content_hash() != b.content_hash()
    with pytest.raises(AnytipError, match="no such run"):
        a.content_hash(["FT-404_o0_20240501T120000Z"])


def test_remove_run_and_unit(reg):
    reg.add_runs([make_run("FT-1"), make_run("FT-1", -45), make_run("FT-2")])
    (gone,) = reg.remove("FT-1_o-45_20240501T120000Z")
    assert not (reg.root / gone.path).exists()
    removed = reg.remove("FT-1")
    assert [r.unit for r in removed] == ["FT-1"] and reg.units() == ["FT-2"]
    assert not (reg.root / "runs" / "FT-1").exists()
    assert reg.verify().ok
    with pytest.raises(AnytipError, match="no run or unit"):
        reg.remove("FT-1")


def damage_chunk(path: Path, dataset: str) -> None:
    """Overwrite bytes inside the first stored chunk of `dataset` (as a bad disk would)."""
    with h5py.File(path, "r") as f:
        info = f[dataset].id.get_chunk_info(0)
    raw = bytearray(path.read_bytes())
    middle = info.byte_offset + info.size // 2
    raw[middle: middle + 8] = bytes(b ^ 0xFF for b in raw[middle: middle + 8])
    path.write_bytes(bytes(raw))


def test_verify_finds_missing_corrupt_and_orphaned(reg):
    recs = reg.add_runs([make_run(f"FT-{i}", n=3000, seed=i) for i in range(4)])
    assert reg.verify().ok and reg.verify().checked == 4
    (reg.root / recs[0].path).unlink()
    damage_chunk(reg.root / recs[1].path, "force")
    write_run(make_run("FT-2", seed=99), reg.root / recs[2].path)  # valid file, other values
    orphan = reg.root / "runs" / "FT-3" / "stray.h5"
    orphan.write_bytes(b"x")
    report = reg.verify()
    assert not report.ok
    assert report.missing == [recs[0].run_id]
    assert sorted(r for r, _ in report.corrupt) == [recs[1].run_id, recs[2].run_id]
    assert report.orphans == ["runs/FT-3/stray.h5"]
    assert len(report.problems()) == 4
    with pytest.raises(AnytipError, match="missing"):
        reg.open_run(recs[0].run_id)
    with pytest.raises(AnytipError, match="changed since import"):
        reg.open_run(recs[2].run_id)


def test_orphans_are_swept_by_the_next_write(reg):
    stray = reg.root / "runs" / "FT-9" / "FT-9_o0_20240501T120000Z.h5"
    stray.parent.mkdir(parents=True)
    stray.write_bytes(b"left by a dead process")
    assert reg.verify().orphans == ["runs/FT-9/FT-9_o0_20240501T120000Z.h5"]
    reg.add_runs([make_run("FT-9")])
    assert reg.verify().ok and reg.open_run("FT-9_o0_20240501T120000Z")


# ---- hostile ids and crafted catalog rows --------------------------------------------------


@pytest.mark.parametrize("sensor_id", ["..", ".", "../x", "/abs/path", "a/b", "x" * 65])
def test_hostile_sensor_ids_are_refused(reg, sensor_id):
    with pytest.raises(AnytipError, match="sensor_id"):
        reg.add_runs([make_run(sensor_id)])
    assert snapshot(reg) == ([], [])


def craft_row(reg: Registry, **values) -> RunRecord:
    rec = RunRecord(**{**make_row_values(), **values})
    with sqlite3.connect(reg.db_path) as conn:
        conn.execute(f"INSERT INTO runs VALUES ({', '.join('?' * len(catalog.COLUMNS))})",
                     catalog.astuple(rec))
    return rec


def make_row_values() -> dict:
    return dict(run_id="FT-1_o0_20240501T120000Z", unit="FT-1", sensor_model="m",
                orientation_deg=0.0, source="rig", rows=1, channels=8, duration_s=0.005,
                protocol=None, sha256="0" * 64, created="2024-05-01T12:00:00Z",
                path="runs/FT-1/FT-1_o0_20240501T120000Z.h5", imported_at="2024-05-01T12:00:00Z")


@pytest.mark.parametrize("values", [
    dict(run_id="../../outside", path="../../outside.h5"),
    dict(unit="..", path="runs/../FT-1_o0_20240501T120000Z.h5"),
    dict(run_id="..", unit="FT-1", path="runs/FT-1/...h5"),
    dict(path="/etc/passwd"),
    dict(path="../outside.h5"),
])
def test_crafted_catalog_rows_cannot_escape(reg, tmp_path, values):
    sentinel = tmp_path / "outside.h5"
    write_run(make_run(), sentinel)
    rec = craft_row(reg, **values)
    with pytest.raises(AnytipError, match="catalog row"):
        reg.payload_path(rec.run_id)
    with pytest.raises(AnytipError, match="catalog row"):
        reg.open_run(rec.run_id)
    with pytest.raises(AnytipError, match="catalog row"):
        reg.export(rec.run_id, tmp_path / "out")
    report = reg.verify()
    assert [r for r, _ in report.bad_rows] == [rec.run_id] and not report.ok
    assert reg.remove(rec.run_id) == [rec]
    reg.add_runs([make_run("FT-2")])
    assert sentinel.is_file() and read_run(sentinel).sensor_id == "FT-0001"
    assert reg.verify().ok


def test_symlink_under_runs_is_an_orphan_not_followed(reg, tmp_path):
    outside = tmp_path / "keep"
    outside.mkdir()
    (outside / "precious.h5").write_text("keep me")
    os.symlink(outside, reg.root / "runs" / "FT-7")
    assert reg.verify().orphans == ["runs/FT-7"]
    reg.add_runs([make_run()])
    assert (outside / "precious.h5").read_text() == "keep me"
    assert not (reg.root / "runs" / "FT-7").exists() and reg.verify().ok


# ---- interruptions ---------------------------------------------------------------------------


def test_interrupted_rename_leaves_registry_unchanged(reg, monkeypatch):
    reg.add_runs([make_run("FT-0")])
    before, hash_before = snapshot(reg), reg.content_hash()
    real_replace, calls = os.replace, []

    def flaky_replace(src, dst):
        calls.append(dst)
        if len(calls) == 2:
            raise OSError("disk pulled out")
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", flaky_replace)
    with pytest.raises(OSError, match="disk pulled out"):
        reg.add_runs([make_run("FT-1"), make_run("FT-2"), make_run("FT-3")])
    monkeypatch.undo()
    assert len(calls) == 2
    assert snapshot(reg) == before and reg.content_hash() == hash_before
    assert reg.verify().ok


def test_interrupted_insert_leaves_registry_unchanged(reg, monkeypatch):
    reg.add_runs([make_run("FT-0")])
    before = snapshot(reg)
    real_insert, calls = catalog.insert, []

    def failing_insert(conn, record):
        calls.append(record.run_id)
        if len(calls) == 2:
            raise KeyboardInterrupt
        real_insert(conn, record)

    monkeypatch.setattr(catalog, "insert", failing_insert)
    with pytest.raises(KeyboardInterrupt):
        reg.add_runs([make_run("FT-1"), make_run("FT-2")])
    monkeypatch.undo()
    assert snapshot(reg) == before and reg.verify().ok
    assert [r.unit for r in reg.add_runs([make_run("FT-1")])] == ["FT-1"]


def test_refused_add_leaves_no_scratch_files(reg):
    bad = make_run("FT-2")
    bad.pressure[3, 3] = np.inf
    with pytest.raises(AnytipError) as info:
        reg.add_runs([make_run("FT-1"), bad], source_paths=["one.h5", "two.h5"])
    assert "two.h5" in str(info.value) and "pressure" in str(info.value)
    assert snapshot(reg) == ([], [])


# ---- protocols marked in the registry ------------------------------------------------------


def test_a_catalog_of_schema_version_2_gains_protocol_marks_and_keeps_its_hash(tmp_path):
    reg = Registry(tmp_path / "reg")
    reg.add_runs([make_run("FT-1"), make_run("FT-2", protocol="full")])
    before = reg.content_hash()
    with sqlite3.connect(reg.db_path) as conn:  # as a catalog written before protocols could be marked
        conn.execute("ALTER TABLE runs DROP COLUMN protocol_set")
        conn.execute("PRAGMA user_version = 2")
    reg = Registry(tmp_path / "reg")
    assert [(r.protocol, r.protocol_set) for r in reg.list_runs()] == [(None, False), ("full", False)]
    assert reg.content_hash() == before
    with sqlite3.connect(reg.db_path) as conn:
        assert conn.execute("PRAGMA user_version").fetchone()[0] == catalog.SCHEMA_VERSION


def test_set_protocol_marks_a_measured_unit_and_changes_the_hash(reg):
    runs = [make_run("FT-1", source="rig"), make_run("FT-1", -45, source="rig"), make_run("FT-2")]
    reg.add_runs(runs)
    files, before = snapshot(reg)[1], reg.content_hash()
    marked = reg.set_protocol("FT-1", "retest")
    assert [(r.protocol, r.protocol_set) for r in marked] == [("retest", True)] * 2
    assert [r.unit for r in reg.list_runs(protocol="retest")] == ["FT-1", "FT-1"]
    assert reg.content_hash() != before and snapshot(reg)[1] == files  # the files stay as they were
    unmarked = make_run_id(runs[2])  # a run without a mark hashes as before marks existed
    assert reg.content_hash([unmarked]) == catalog.hash_pairs([(unmarked, runs[2].content_hash())])
    (one,) = reg.set_protocol(make_run_id(runs[1]), "plan120")
    assert one.protocol == "plan120" and reg.record(make_run_id(runs[0])).protocol == "retest"
    reg.set_protocol("FT-1", None)
    assert reg.content_hash() == before and all(r.protocol is None for r in reg.list_runs())


def test_a_protocol_the_file_names_is_kept(reg):
    reg.add_runs([make_run("FT-1", protocol="full"), make_run("FT-1", -45)])
    with pytest.raises(AnytipError, match=r"FT-1_o0_20240501T120000Z: its file names protocol 'full'"):
        reg.set_protocol("FT-1", "retest")
    assert [r.protocol for r in reg.list_runs()] == [None, "full"]  # all or nothing
    assert [r.protocol_set for r in reg.set_protocol("FT-1", "full")] == [True, False]
    assert [r.protocol for r in reg.set_protocol("FT-1", None)] == [None, "full"]
    with pytest.raises(AnytipError, match=r"protocol 'a b' must match"):
        reg.set_protocol("FT-1", "a b")


def test_import_marks_its_runs_in_one_transaction(reg, tmp_path):
    runs = [make_run("FT-1", source="rig"), make_run("FT-1", -45, source="rig")]
    paths = write_files(tmp_path / "in", runs)
    report = reg.import_paths(paths[:1], protocol="retest")
    assert [(r.protocol, r.protocol_set) for r in report.added] == [("retest", True)]
    report = reg.import_paths(paths, protocol="retest")  # the unchanged one keeps its mark
    assert len(report.added) == 1 and [r.protocol for r in reg.list_runs()] == ["retest", "retest"]
    state = snapshot(reg)
    with pytest.raises(AnytipError, match=r"the registry marks it protocol 'retest' \(change a mark"):
        reg.import_paths(paths, protocol="plan120")
    simulated = write_files(tmp_path / "sim", [make_run("FT-2", protocol="full")])
    with pytest.raises(AnytipError, match=r"FT-2_o0_20240501T120000Z: its file names protocol 'full'"):
        reg.import_paths(simulated + [write_run(make_run("FT-3"), tmp_path / "x.h5")], protocol="retest")
    assert snapshot(reg) == state


def test_a_marked_test_session_is_read_as_one(reg):
    from anytip.data.arrays import load_arrays
    from anytip.data.plans import test_session_rows

    runs = [make_run("FT-1", source="rig", n=200, seed=1), make_run("FT-1", -45, source="rig", n=200, seed=2)]
    reg.add_runs(runs)
    assert not test_session_rows(load_arrays(reg, reg.list_runs())).any()
    reg.set_protocol(make_run_id(runs[1]), "retest")
    arrays = load_arrays(reg, reg.list_runs())
    expected = [k for k, r in enumerate(arrays.runs) if r.run_id == make_run_id(runs[1])]
    assert np.array_equal(test_session_rows(arrays), np.isin(arrays.run, expected))
