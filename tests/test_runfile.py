"""The interchange format: every rejection CALIBRATION_FORMAT.md lists, foreign files, round trips."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from anytip.data.runfile import (
    REQUIRED_ATTRS,
    REQUIRED_DATASETS,
    V1_TARGET_DATASETS,
    CalibrationRun,
    RunFormatError,
    Target,
    check_sensor_id,
    read_run,
    write_run,
)
from anytip.errors import AnytipError
from run_factory import make_run

N, C = 20, 8


def good_contents() -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """Attributes and datasets of a valid file, for tests to spoil one thing."""
    g = np.random.default_rng(1)
    attrs = {
        "format": "calibration_run", "format_version": 1, "sensor_id": "FT-0007",
        "sensor_model": "fingertip-8baro-r10", "orientation_deg": -45.0, "sample_rate_hz": 200.0,
        "source": "rig", "created": "2024-05-01T12:00:00Z",
    }
    data = {
        "time": np.arange(N) / 200.0,
        "pressure": (1e5 + g.standard_normal((N, C))).astype(np.float32),
        "force": g.standard_normal((N, 3)).astype(np.float32),
        "angles": g.standard_normal((N, 2)).astype(np.float32),
        "temperature": np.full((N, C), 25.0, np.float32),
        "in_contact": np.arange(N) % 2 == 0,
    }
    return attrs, data


def write_plain(path: Path, attrs: dict[str, Any], data: dict[str, np.ndarray]) -> Path:
    """Write with plain h5py, the way another program would (no chunking or compression)."""
    with h5py.File(path, "w") as f:
        f.attrs.update(attrs)
        for name, arr in data.items():
            f.create_dataset(name, data=arr)
    return path


def refused(path: Path, *words: str) -> RunFormatError:
    """Assert read_run refuses `path` with a message naming the file and every word."""
    with pytest.raises(RunFormatError) as info:
        read_run(path)
    message = str(info.value)
    assert isinstance(info.value, AnytipError)
    assert str(path) in message
    for word in words:
        assert word in message, message
    return info.value


def spoiled(tmp_path: Path, attrs_change: dict | None = None, data_change: dict | None = None,
            drop: tuple[str, ...] = ()) -> Path:
    attrs, data = good_contents()
    attrs.update(attrs_change or {})
    data.update(data_change or {})
    for key in drop:
        attrs.pop(key, None)
        data.pop(key, None)
    return write_plain(tmp_path / "run.h5", attrs, data)


def test_good_file_is_accepted(tmp_path):
    run = read_run(spoiled(tmp_path))
    assert run.sensor_id == "FT-0007" and run.n_rows == N and run.n_channels == C


@pytest.mark.parametrize("attr", REQUIRED_ATTRS)
def test_missing_attribute(tmp_path, attr):
    refused(spoiled(tmp_path, drop=(attr,)), "missing root attribute", attr)


@pytest.mark.parametrize("name", REQUIRED_DATASETS + V1_TARGET_DATASETS)
def test_missing_dataset(tmp_path, name):
    refused(spoiled(tmp_path, drop=(name,)), "missing dataset", name)


def test_wrong_format(tmp_path):
    refused(spoiled(tmp_path, {"format": "something_else"}), "format", "something_else")


@pytest.mark.parametrize("version", [0, 3, 99])
def test_unknown_format_version(tmp_path, version):
    refused(spoiled(tmp_path, {"format_version": version}), "format_version", str(version))


def test_format_version_not_an_integer(tmp_path):
    refused(spoiled(tmp_path, {"format_version": "1"}), "format_version", "integer")


@pytest.mark.parametrize("name", ["pressure", "force", "angles", "temperature", "in_contact"])
def test_row_counts_differ(tmp_path, name):
    _, data = good_contents()
    refused(spoiled(tmp_path, data_change={name: data[name][:-1]}), name, "rows", str(N - 1))


@pytest.mark.parametrize(("name", "shape"), [
    ("force", (N, 4)), ("force", (N, 2)), ("angles", (N, 3)), ("temperature", (N, C + 1)),
])
def test_wrong_column_count(tmp_path, name, shape):
    refused(spoiled(tmp_path, data_change={name: np.zeros(shape, np.float32)}), name, "columns")


def test_wrong_dimensions(tmp_path):
    refused(spoiled(tmp_path, data_change={"force": np.zeros(N, np.float32)}), "force", "dimension")


@pytest.mark.parametrize("name", ["pressure", "force", "angles"])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_values(tmp_path, name, bad):
    _, data = good_contents()
    arr = data[name].copy()
    arr[5, 1] = bad
    refused(spoiled(tmp_path, data_change={name: arr}), name, "NaN or infinite", "row 5")


def test_decreasing_time(tmp_path):
    time = np.arange(N) / 200.0
    time[7] = time[5]
    refused(spoiled(tmp_path, data_change={"time": time}), "time", "decreases", "row 7")


def test_equal_times_are_allowed(tmp_path):
    time = np.arange(N) / 200.0
    time[7] = time[6]
    assert read_run(spoiled(tmp_path, data_change={"time": time})).n_rows == N


@pytest.mark.parametrize("sensor_id", [
    ".", "..", "../x", "a/b", "/abs", "FT 7", "", "x" * 65, "FT\n1", "FT-é",
])
def test_sensor_id_outside_pattern(tmp_path, sensor_id):
    refused(spoiled(tmp_path, {"sensor_id": sensor_id}), "sensor_id")


def test_check_sensor_id():
    assert check_sensor_id("FT-0007.a_b") == "FT-0007.a_b"
    assert check_sensor_id("x" * 64)
    for bad in (".", "..", "...", "a/b", "x" * 65, 7):
        with pytest.raises(ValueError):
            check_sensor_id(bad)


def test_not_hdf5(tmp_path):
    path = tmp_path / "run.h5"
    path.write_text("time,pressure\n0,1\n")
    refused(path, "not a readable HDF5 file")


def test_truncated_hdf5(tmp_path):
    path = tmp_path / "run.h5"
    write_run(make_run(n=2000), path)
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    refused(path, "truncated")


def test_corrupt_chunk_fails_checksum(tmp_path):
    path = tmp_path / "run.h5"
    write_run(make_run(n=4000), path, compression=None)
    raw = bytearray(path.read_bytes())
    with h5py.File(path, "r") as f:
        offset = f["pressure"].id.get_chunk_info(0).byte_offset
    raw[offset + 100: offset + 108] = b"\xff" * 8
    path.write_bytes(bytes(raw))
    refused(path, "pressure", "cannot be read")


def test_missing_file(tmp_path):
    refused(tmp_path / "nope.h5", "no such file")


def test_source_outside_allowed(tmp_path):
    refused(spoiled(tmp_path, {"source": "guess"}), "source", "guess")


def test_file_from_another_program_is_accepted(tmp_path):
    """Fixed-length byte strings, int orientation, no compression, in_contact as uint8 0/1."""
    attrs, data = good_contents()
    fixed = {k: np.bytes_(v.encode()) for k, v in attrs.items() if isinstance(v, str)}
    attrs.update(fixed, orientation_deg=np.int32(-90), format_version=np.int64(1))
    attrs["notes"] = np.bytes_(b"logged by rigctl 2.1")
    data["in_contact"] = data["in_contact"].astype(np.uint8)
    path = write_plain(tmp_path / "foreign.h5", attrs, data)
    with h5py.File(path, "r") as f:
        assert f.attrs["sensor_id"].dtype.kind == "S" and f["pressure"].compression is None
    run = read_run(path)
    assert run.sensor_id == "FT-0007" and run.orientation_deg == -90.0
    assert isinstance(run.orientation_deg, float) and run.extra == {"notes": "logged by rigctl 2.1"}
    assert run.in_contact.dtype == np.bool_
    np.testing.assert_array_equal(run.in_contact, data["in_contact"] == 1)
    np.testing.assert_array_equal(run.pressure, data["pressure"])


def test_in_contact_other_than_0_1_refused(tmp_path):
    flags = np.zeros(N, np.uint8)
    flags[3] = 2
    refused(spoiled(tmp_path, data_change={"in_contact": flags}), "in_contact")


def test_write_refuses_invalid_run_and_writes_nothing(tmp_path):
    run = make_run()
    run.force[0, 0] = np.nan
    with pytest.raises(RunFormatError, match="force"):
        write_run(run, tmp_path / "x.h5")
    assert not (tmp_path / "x.h5").exists()


@pytest.mark.parametrize("text", ["a\x00b", "\ud800"])
def test_write_refuses_text_hdf5_cannot_store(tmp_path, text):
    run = make_run()
    run.extra["notes"] = text
    with pytest.raises(RunFormatError, match="notes"):
        write_run(run, tmp_path / "x.h5")
    assert not (tmp_path / "x.h5").exists()


def test_written_file_is_chunked_compressed_checksummed(tmp_path):
    path = write_run(make_run(), tmp_path / "run.h5")
    with h5py.File(path, "r") as f:
        for name in ("time", "pressure", "force", "angles"):
            assert f[name].chunks and f[name].compression == "gzip" and f[name].fletcher32


def assert_same_run(a: CalibrationRun, b: CalibrationRun) -> None:
    assert a.attrs() == b.attrs()
    assert a.target_layout == b.target_layout
    assert a.datasets().keys() == b.datasets().keys()
    for name, arr in a.datasets().items():
        other = b.datasets()[name]
        assert arr.shape == other.shape
        assert np.ascontiguousarray(arr, other.dtype).tobytes() == other.tobytes(), name
    assert a.content_hash() == b.content_hash()


def test_round_trip_changes_no_value(tmp_path):
    run = make_run(protocol="full")
    assert_same_run(run, read_run(write_run(run, tmp_path / "run.h5")))


finite32 = st.floats(-1e6, 1e6, width=32, allow_subnormal=False)
absolute32 = st.floats(0.5, 16000000.0, width=32)  # inside PRESSURE_RANGE_PA
hdf5_text = st.text(st.characters(exclude_categories=("Cs",), exclude_characters="\x00"), max_size=20)


@st.composite
def small_runs(draw) -> CalibrationRun:
    """Valid runs of either version: v1 with the fingertip's targets, v2 with 1-3 named targets."""
    n = draw(st.integers(1, 12))
    c = draw(st.integers(1, 9))
    steps = draw(hnp.arrays(np.float64, n, elements=st.floats(0, 10)))
    optional = draw(st.booleans())
    version = draw(st.sampled_from([1, 2]))
    if version == 1:
        targets = {"force": draw(hnp.arrays(np.float32, (n, 3), elements=finite32)),
                   "angles": draw(hnp.arrays(np.float32, (n, 2), elements=finite32))}
        fields = {"force": targets["force"], "angles": targets["angles"]}
    else:
        names = draw(st.lists(st.from_regex(r"[A-Za-z][A-Za-z0-9_]{0,10}", fullmatch=True), min_size=1,
                              max_size=3, unique=True))
        fields = {"targets": {}}
        for name in names:
            k = draw(st.integers(1, 4))
            comps = draw(st.lists(hdf5_text.filter(str.strip), min_size=k, max_size=k, unique=True))
            fields["targets"][name] = Target(draw(hnp.arrays(np.float32, (n, k), elements=finite32)),
                                             draw(hdf5_text.filter(str.strip)), tuple(comps))
    common = dict(
        sensor_id=draw(st.from_regex(r"[A-Za-z0-9_-][A-Za-z0-9._-]{0,20}", fullmatch=True)),
        sensor_model=draw(st.from_regex(r"[A-Za-z0-9_-][A-Za-z0-9._-]{0,20}", fullmatch=True)),
        orientation_deg=draw(st.floats(-180, 180)),
        sample_rate_hz=draw(st.floats(1, 1e4)),
        source=draw(st.sampled_from(["rig", "simulated", "import"])),
        created="2024-05-01T12:00:00Z",
        time=np.cumsum(steps),
        pressure=draw(hnp.arrays(np.float32, (n, c), elements=absolute32)),
        temperature=draw(hnp.arrays(np.float32, (n, c), elements=finite32)) if optional else None,
        in_contact=draw(hnp.arrays(np.bool_, n)) if optional else None,
        extra={"notes": draw(hdf5_text)} if optional else {},
    )
    if version == 1:
        return CalibrationRun.fingertip(**common, **fields)
    return CalibrationRun(**common, **fields, format_version=2)


@settings(max_examples=40, deadline=None)
@given(small_runs())
def test_round_trip_property(run):
    with tempfile.TemporaryDirectory() as tmp:
        back = read_run(write_run(run, Path(tmp) / "run.h5"))
    assert_same_run(run, back)
