"""Format version 2: named targets written with raw h5py from CALIBRATION_FORMAT.md alone,
the refusals the spec lists for them, v1 read as v2, and conversions between the versions."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from anytip.data.runfile import V1_LAYOUT, RunFormatError, Target, TargetLayout, read_run, write_run
from anytip.errors import AnytipError
from run_factory import make_run

N = 30


def edge_file(path: Path, *, attrs: dict[str, Any] | None = None, targets: dict | None = None,
              drop_attr: tuple[str, ...] = (), root: dict[str, np.ndarray] | None = None) -> Path:
    """A v2 run of a 4-barometer edge sensor (targets position and depth, in m), written the way
    another lab's logger would: plain h5py, fixed-length strings, no chunking."""
    g = np.random.default_rng(0)
    base = {"format": "calibration_run", "format_version": 2, "sensor_id": "EDGE-01",
            "sensor_model": "edge-4baro", "sample_rate_hz": 100.0, "source": "rig",
            "created": "2025-03-01T09:30:00Z"}
    base.update(attrs or {})
    for key in drop_attr:
        base.pop(key)
    if targets is None:
        targets = {
            "position": (g.uniform(0, 0.04, (N, 1)).astype(np.float32), {"unit": "m", "components": ["x"]}),
            "depth": (g.uniform(0, 0.003, (N, 1)).astype(np.float32), {"unit": "m", "components": ["z"]}),
        }
    with h5py.File(path, "w") as f:
        for k, v in base.items():
            f.attrs[k] = np.bytes_(v.encode()) if isinstance(v, str) else v
        f["time"] = np.arange(N) / 100.0
        f["pressure"] = (1e5 + g.standard_normal((N, 4))).astype(np.float32)
        group = f.create_group("targets")
        for name, (values, tattrs) in targets.items():
            group[name] = values
            for k, v in tattrs.items():
                group[name].attrs[k] = v
        for name, values in (root or {}).items():
            f[name] = values
    return path


def refused(path: Path, *words: str) -> None:
    with pytest.raises(RunFormatError) as info:
        read_run(path)
    message = str(info.value)
    assert str(path) in message
    for word in words:
        assert word in message, message


def test_a_v2_file_from_the_spec_reads_with_its_targets(tmp_path):
    run = read_run(edge_file(tmp_path / "edge.h5"))
    assert run.format_version == 2 and run.n_channels == 4 and run.orientation_deg == 0.0
    assert run.target_layout == {"depth": TargetLayout("m", ("z",)), "position": TargetLayout("m", ("x",))}
    assert run.target("position").shape == (N, 1) and run.in_contact is None
    with pytest.raises(AnytipError, match="no target 'force'.*depth.*position"):
        _ = run.force


def test_v2_round_trip_changes_no_value(tmp_path):
    run = read_run(edge_file(tmp_path / "edge.h5"))
    back = read_run(write_run(run, tmp_path / "again.h5"))
    assert back.target_layout == run.target_layout and back.content_hash() == run.content_hash()
    for name, t in run.targets.items():
        np.testing.assert_array_equal(back.target(name), t.values)
    np.testing.assert_array_equal(back.pressure, run.pressure)


def test_target_order_does_not_change_the_hash():
    run = make_run().as_version(2)
    swapped = run.as_version(2)
    swapped.targets = dict(reversed(list(run.targets.items())))
    assert swapped.content_hash() == run.content_hash()


def test_the_unit_and_components_are_part_of_the_content():
    run = make_run().as_version(2)
    other = run.as_version(2)
    other.targets = {**run.targets, "force": Target(run.force, "kN", ("fx", "fy", "fz"))}
    assert other.content_hash() != run.content_hash()


@pytest.mark.parametrize(("targets", "words"), [
    ({"depth": (np.zeros((N, 1), np.float32), {"components": ["z"]})}, ["targets/depth", "'unit'"]),
    ({"depth": (np.zeros((N, 1), np.float32), {"unit": "m"})}, ["targets/depth", "'components'"]),
    ({"depth": (np.zeros((N, 2), np.float32), {"unit": "m", "components": ["z"]})},
     ["targets/depth", "1 columns", "components"]),
    ({"depth": (np.zeros((N, 1), np.float32), {"unit": "", "components": ["z"]})}, ["'unit'", "non-empty"]),
    ({"depth": (np.zeros((N, 2), np.float32), {"unit": "m", "components": ["z", "z"]})}, ["twice"]),
    ({"depth": (np.zeros((N, 1), np.float32), {"unit": "m", "components": [1]})}, ["components"]),
    ({"depth": (np.zeros((N - 1, 1), np.float32), {"unit": "m", "components": ["z"]})},
     ["targets/depth", "rows"]),
    ({"depth": (np.full((N, 1), np.nan, np.float32), {"unit": "m", "components": ["z"]})},
     ["targets/depth", "NaN"]),
    ({"9lives": (np.zeros((N, 1), np.float32), {"unit": "m", "components": ["z"]})}, ["target name"]),
    ({"depth": (np.array(["a"] * N, dtype="S1"), {"unit": "m", "components": ["z"]})}, ["numeric"]),
    ({}, ["at least one target"]),
])
def test_bad_targets_are_refused(tmp_path, targets, words):
    refused(edge_file(tmp_path / "bad.h5", targets=targets), *words)


def test_v2_without_the_targets_group_is_refused(tmp_path):
    path = edge_file(tmp_path / "bad.h5")
    with h5py.File(path, "a") as f:
        del f["targets"]
    refused(path, "missing group 'targets'")


def test_v2_with_root_targets_is_refused(tmp_path):
    refused(edge_file(tmp_path / "bad.h5", root={"force": np.zeros((N, 3), np.float32)}),
            "group 'targets'", "'force'")


def test_v2_targets_stored_outside_the_file_are_refused(tmp_path):
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["depth"] = np.zeros((N, 1), np.float32)
    path = edge_file(tmp_path / "bad.h5", targets={"position": (np.zeros((N, 1), np.float32),
                                                                {"unit": "m", "components": ["x"]})})
    with h5py.File(path, "a") as f:
        f["targets"]["depth"] = h5py.ExternalLink(str(other), "depth")
    refused(path, "external link")


def test_orientation_is_required_in_v1_only(tmp_path):
    run = read_run(edge_file(tmp_path / "edge.h5", attrs={"orientation_deg": -45.0}))
    assert run.orientation_deg == -45.0
    path = edge_file(tmp_path / "v1.h5", attrs={"format_version": 1})
    refused(path, "orientation_deg")


def test_sensor_model_outside_the_pattern_is_refused(tmp_path):
    refused(edge_file(tmp_path / "bad.h5", attrs={"sensor_model": "edge 4/baro"}), "sensor_model")


def old_v1_hash(run) -> str:
    """The content hash as version 1 defined it: attributes, then each dataset by name."""
    h = hashlib.sha256()
    h.update(json.dumps(run.attrs(), sort_keys=True).encode())
    data = {"time": run.time, "pressure": run.pressure, "force": run.force, "angles": run.angles,
            "temperature": run.temperature, "in_contact": run.in_contact}
    for name, arr in data.items():
        if arr is None:
            continue
        dtype = {"time": "<f8", "in_contact": "|b1"}.get(name, "<f4")
        arr = np.ascontiguousarray(arr, dtype=np.dtype(dtype))
        h.update(f"{name}:{arr.dtype.str}:{arr.shape}".encode())
        h.update(arr.tobytes())
    return h.hexdigest()


@pytest.mark.parametrize("optional", [True, False])
def test_a_v1_run_keeps_its_content_hash(tmp_path, optional):
    run = read_run(write_run(make_run(optional=optional), tmp_path / "v1.h5"))
    assert run.format_version == 1 and run.target_layout == V1_LAYOUT
    assert run.content_hash() == old_v1_hash(run)
    with h5py.File(tmp_path / "v1.h5") as f:
        assert "force" in f and "targets" not in f


def test_v1_and_v2_convert_both_ways_without_changing_a_value(tmp_path):
    v1 = make_run()
    v2 = read_run(write_run(v1.as_version(2), tmp_path / "v2.h5"))
    assert v2.format_version == 2 and v2.target_layout == V1_LAYOUT
    with h5py.File(tmp_path / "v2.h5") as f:
        assert list(f["targets"]) == ["angles", "force"] and "force" not in f
        assert f["targets/force"].attrs["unit"] == "N"
    back = read_run(write_run(v2.as_version(1), tmp_path / "v1.h5"))
    assert back.content_hash() == v1.content_hash()
    np.testing.assert_array_equal(back.angles, v1.angles)


def test_only_the_fingertip_layout_converts_to_v1(tmp_path):
    run = read_run(edge_file(tmp_path / "edge.h5"))
    with pytest.raises(AnytipError, match="version 1 holds only force"):
        run.as_version(1)


def test_a_registry_takes_v2_runs_and_exports_either_version(tmp_path):
    from anytip.data.registry import Registry

    reg = Registry(tmp_path / "reg")
    v1 = make_run("FT-9", n=200)
    reg.add_runs([v1])
    reg.import_paths([edge_file(tmp_path / "edge.h5")])
    (as_v2,) = reg.export("FT-9", tmp_path / "v2", format_version=2)
    again = read_run(as_v2)
    assert again.format_version == 2 and again.target_layout == V1_LAYOUT
    np.testing.assert_array_equal(again.force, v1.force)
    (as_is,) = reg.export("FT-9", tmp_path / "same")
    assert read_run(as_is).content_hash() == v1.content_hash()
    (edge,) = reg.export("EDGE-01", tmp_path / "edge")
    assert read_run(edge).format_version == 2
    with pytest.raises(AnytipError, match="cannot be written as format version 1"):
        reg.export("EDGE-01", tmp_path / "edge_v1", format_version=1)
    assert not (tmp_path / "edge_v1").exists()


def test_a_registry_refuses_a_run_whose_targets_disagree_with_its_sensor_model(tmp_path):
    from anytip.data.registry import Registry

    reg = Registry(tmp_path / "reg")
    reg.import_paths([edge_file(tmp_path / "edge.h5")])
    other = {"position": (np.zeros((N, 1), np.float32), {"unit": "mm", "components": ["x"]}),
             "depth": (np.zeros((N, 1), np.float32), {"unit": "m", "components": ["z"]})}
    path = edge_file(tmp_path / "mm.h5", attrs={"sensor_id": "EDGE-02"}, targets=other)
    with pytest.raises(AnytipError, match=r"mm\.h5.*'edge-4baro' has 4 pressure channels and the targets "
                                          r".*position \[m\].*this run has .*position \[mm\]"):
        reg.import_paths([path])
    assert reg.units() == ["EDGE-01"]
    fingertip_as_v2 = make_run("FT-1").as_version(2)
    reg.add_runs([make_run("FT-2")])
    reg.add_runs([fingertip_as_v2])  # the same layout in either version
    assert sorted(reg.units()) == ["EDGE-01", "FT-1", "FT-2"]


def test_a_sensor_model_with_no_runs_left_may_take_a_new_layout(tmp_path):
    from anytip.data.registry import Registry

    reg = Registry(tmp_path / "reg")
    reg.import_paths([edge_file(tmp_path / "edge.h5")])
    reg.remove("EDGE-01")
    other = {"position": (np.zeros((N, 1), np.float32), {"unit": "mm", "components": ["x"]})}
    reg.import_paths([edge_file(tmp_path / "mm.h5", attrs={"sensor_id": "EDGE-02"}, targets=other)])
    assert reg.units() == ["EDGE-02"]


def test_a_catalog_of_schema_version_1_learns_its_layouts_from_its_runs(tmp_path):
    import sqlite3

    from anytip.data import catalog
    from anytip.data.registry import Registry

    reg = Registry(tmp_path / "reg")
    reg.add_runs([make_run("FT-1")])
    with sqlite3.connect(reg.db_path) as conn:  # as a catalog written before layouts were recorded
        conn.execute("DROP TABLE sensor_models")
        conn.execute("ALTER TABLE runs DROP COLUMN protocol_set")
        conn.execute("PRAGMA user_version = 1")
    reg = Registry(tmp_path / "reg")
    with pytest.raises(AnytipError, match=r"'fingertip-8baro-r10' has 8 pressure channels .*\(run FT-1"):
        reg.add_runs([make_run("FT-2", channels=7)])
    reg.add_runs([make_run("FT-3")])
    with sqlite3.connect(reg.db_path) as conn:
        assert conn.execute("PRAGMA user_version").fetchone()[0] == catalog.SCHEMA_VERSION
        models = [m for (m,) in conn.execute("SELECT sensor_model FROM sensor_models")]
    assert models == ["fingertip-8baro-r10"]
