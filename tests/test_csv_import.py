"""Rig CSV logs: the 34-column map, sidecars, conversions, errors with line and column, speed."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from anytip.data.csv_import import (
    DEFAULT_COLUMN_MAP,
    CsvFormatError,
    load_column_map,
    read_csv_run,
)
from anytip.data.registry import Registry
from anytip.data.runfile import read_run
from anytip.errors import AnytipError
from anytip.rundir import builtin

HEADER = (["time", "Fx", "Fy", "Fz", "Mx", "My", "Mz"] + [f"s{i}" for i in range(1, 9)]
          + [f"t{i}" for i in range(1, 9)] + ["theta", "phi", "in_contact"]
          + ["x", "y", "z", "qw", "qx", "qy", "qz", "seq"])


def rig_table(n: int, seed: int = 0) -> np.ndarray:
    """(n, 34) float64 values of a plausible rig log, in the rig34 units."""
    g = np.random.default_rng(seed)
    t = np.zeros((n, 34))
    t[:, 0] = np.arange(n) / 200.0
    t[:, 1:4] = g.uniform(-10, 10, (n, 3))
    t[:, 4:7] = g.standard_normal((n, 3)) * 0.01
    t[:, 7:15] = np.round(1e5 + g.standard_normal((n, 8)) * 80, 2)
    t[:, 15:23] = np.round(25 + g.standard_normal((n, 8)), 2)
    t[:, 23] = np.round(g.uniform(-45, 45, n), 3)
    t[:, 24] = np.round(g.uniform(-135, 45, n), 3)
    t[:, 25] = g.integers(0, 2, n)
    t[:, 26:29] = g.uniform(-0.1, 0.1, (n, 3))
    t[:, 29] = 1.0
    t[:, 33] = np.arange(n)
    return t


def write_log(path: Path, table: np.ndarray, sidecar: dict | None = None, header: bool = True) -> Path:
    """A rig34 CSV log (and a JSON sidecar) written the way the rig logger would."""
    with open(path, "w") as f:
        if header:
            f.write(",".join(HEADER) + "\n")
        np.savetxt(f, table, delimiter=",", fmt="%.10g")
    if sidecar is not None:
        path.with_suffix(".json").write_text(json.dumps(sidecar))
    return path


SIDECAR = {"sensor_id": "FT-0042", "created": "2024-06-02T09:30:00Z", "operator": "ana"}


@pytest.fixture
def log(tmp_path) -> Path:
    return write_log(tmp_path / "log.csv", rig_table(200), SIDECAR)


def lines_of(path: Path) -> list[str]:
    return path.read_text().splitlines()


def rewrite_line(path: Path, line: int, edit) -> None:
    """Apply `edit(cells) -> cells` to file line `line` (from 1)."""
    lines = lines_of(path)
    lines[line - 1] = ",".join(edit(lines[line - 1].split(",")))
    path.write_text("\n".join(lines) + "\n")


def set_cell(path: Path, line: int, column: int, text: str) -> None:
    def edit(cells):
        cells[column] = text
        return cells
    rewrite_line(path, line, edit)


def csv_error(path: Path, *words: str, line: int | None = None, column: int | None = None) -> CsvFormatError:
    with pytest.raises(CsvFormatError) as info:
        read_csv_run(path)
    msg = str(info.value)
    assert str(path) in msg and isinstance(info.value, AnytipError)
    if line is not None:
        assert info.value.line == line and f"line {line}" in msg, msg
    if column is not None:
        assert f"column {column} ({HEADER[column]})" in msg, msg
    for word in words:
        assert word in msg, msg
    return info.value


def test_default_map_is_the_34_column_rig_log():
    cmap = load_column_map()
    assert DEFAULT_COLUMN_MAP.name == "rig34.yaml" and cmap.n_columns == 34 and cmap.header
    assert len(cmap.columns.pressure) == 8 and cmap.units.angles == "deg"


def test_reads_a_34_column_log(log):
    table = rig_table(200)
    run = read_csv_run(log)
    assert (run.sensor_id, run.created, run.source, run.extra) == (
        "FT-0042", "2024-06-02T09:30:00Z", "rig", {"operator": "ana"})
    assert (run.sensor_model, run.sample_rate_hz, run.orientation_deg) == ("fingertip-8baro-r10", 200.0, 0.0)
    assert run.n_rows == 200 and run.n_channels == 8
    np.testing.assert_array_equal(run.time, table[:, 0])
    np.testing.assert_array_equal(run.force, table[:, 1:4].astype(np.float32))
    np.testing.assert_array_equal(run.pressure, table[:, 7:15].astype(np.float32))
    np.testing.assert_array_equal(run.temperature, table[:, 15:23].astype(np.float32))
    np.testing.assert_allclose(run.angles, np.deg2rad(table[:, 23:25]), rtol=1e-6)
    np.testing.assert_array_equal(run.in_contact, table[:, 25] == 1)


def test_yaml_sidecar_overrides_map_defaults(tmp_path):
    path = write_log(tmp_path / "run7.csv", rig_table(50))
    (tmp_path / "run7.csv.yaml").write_text(yaml.safe_dump({
        "sensor_id": "FT-7", "created": "2024-06-02T11:30:00+02:00", "orientation_deg": -45,
        "sensor_model": "fingertip-8baro-r12", "sample_rate_hz": 100, "source": "import",
    }))
    run = read_csv_run(path)
    assert (run.orientation_deg, run.sensor_model, run.sample_rate_hz, run.source) == (
        -45.0, "fingertip-8baro-r12", 100.0, "import")
    assert run.created == "2024-06-02T09:30:00Z"


def test_yaml_timestamp_in_sidecar(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(10))
    (tmp_path / "log.yaml").write_text("sensor_id: FT-1\ncreated: 2024-06-02T09:30:00Z\n")
    assert read_csv_run(path).created == "2024-06-02T09:30:00Z"


def test_metadata_argument_overrides_sidecar(log):
    assert read_csv_run(log, metadata={"orientation_deg": -90}).orientation_deg == -90.0


def test_missing_sidecar(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(10))
    error = csv_error(path, "sensor_id", "no sidecar")
    assert "log.json" in str(error)


def test_sidecar_without_sensor_id(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(10), {"created": "2024-06-02T09:30:00Z"})
    with pytest.raises(CsvFormatError) as info:
        read_csv_run(path)
    assert str(tmp_path / "log.json") in str(info.value) and "'sensor_id'" in str(info.value)


def test_sidecar_unknown_key_and_bad_time(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(10), {**SIDECAR, "operatr": "x", "created": "noon"})
    with pytest.raises(CsvFormatError) as info:
        read_csv_run(path)
    assert "'operatr' is not allowed" in str(info.value) and "'created'" in str(info.value)


def test_two_sidecars_are_ambiguous(log):
    log.with_suffix(".yaml").write_text("sensor_id: FT-1\n")
    csv_error(log, "more than one sidecar")


def test_hostile_sensor_id_in_sidecar(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(10), {**SIDECAR, "sensor_id": "../x"})
    with pytest.raises(AnytipError, match="sensor_id"):
        read_csv_run(path)


def test_row_with_wrong_column_count(log):
    rewrite_line(log, 8, lambda cells: cells[:-1])
    csv_error(log, "33 columns", "expected 34", line=8)


def test_row_with_extra_column(log):
    rewrite_line(log, 120, lambda cells: cells + ["0"])
    csv_error(log, "35 columns", line=120)


@pytest.mark.parametrize(("line", "column", "text", "problem"), [
    (57, 9, "1013.2hPa", "'1013.2hPa' is not a number"),
    (3, 24, "", "empty cell"),
    (11, 12, "nan", "pressure is NaN or infinite"),
    (9, 8, "0", "pressure 0 Pa"),
    (13, 10, "-35.5", "pressure -35.5 Pa"),
    (14, 7, "3.4e38", "pressure 3.4e+38 Pa"),
    (40, 0, "0.01", "time decreases"),
    (6, 25, "2", "in_contact must be 0 or 1"),
])
def test_bad_cell_named_by_line_and_column(log, line, column, text, problem):
    set_cell(log, line, column, text)
    csv_error(log, problem, line=line, column=column)


def test_text_in_an_ignored_column_is_fine(log):
    set_cell(log, 5, 30, "n/a")
    assert read_csv_run(log).n_rows == 200


def test_blank_lines_do_not_shift_line_numbers(log):
    lines = lines_of(log)
    log.write_text("\n".join(lines[:4] + [""] + lines[4:]) + "\n")
    set_cell(log, 21, 8, "x")
    csv_error(log, line=21, column=8)


def test_header_only_and_empty_file(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(0), SIDECAR)
    csv_error(path, "no data rows")
    path.write_text("")
    csv_error(path, "empty")


def test_custom_map_converts_units(tmp_path):
    """No header, integer columns, hPa, radians, ms, and a flipped normal force."""
    n = 30
    g = np.random.default_rng(3)
    table = np.column_stack([
        np.arange(n) * 5.0,                    # 0: time in ms
        g.uniform(0, 1, (n, 2)),               # 1-2: theta, phi in rad
        g.uniform(0, 20, (n, 3)),              # 3-5: force, Fz logged positive when pressing
        1000 + g.uniform(0, 1, (n, 6)),        # 6-11: pressure in hPa (6 barometers)
    ])
    path = tmp_path / "tiny.tsv.csv"
    np.savetxt(path, table, delimiter=";", fmt="%.9g")
    (tmp_path / "tiny.tsv.json").write_text(json.dumps(SIDECAR))
    map_path = tmp_path / "tiny.yaml"
    map_path.write_text(yaml.safe_dump({
        "name": "tiny", "header": False, "delimiter": ";",
        "columns": {"time": 0, "angles": [1, 2], "force": [3, 4, 5], "pressure": list(range(6, 12))},
        "units": {"time_scale": 1e-3, "pressure_scale": 100.0, "angles": "rad", "force_sign": [1, 1, -1]},
        "defaults": {"sensor_model": "fingertip-6baro", "sample_rate_hz": 200, "orientation_deg": -90},
    }))
    run = read_csv_run(path, map_path)
    assert run.n_channels == 6 and run.temperature is None and run.in_contact is None
    assert run.orientation_deg == -90.0 and run.sensor_model == "fingertip-6baro"
    np.testing.assert_allclose(run.time, table[:, 0] / 1000)
    np.testing.assert_allclose(run.pressure, table[:, 6:] * 100, rtol=1e-7)
    np.testing.assert_allclose(run.force, table[:, 3:6] * [1, 1, -1], rtol=1e-7)
    np.testing.assert_allclose(run.angles, table[:, 1:3], rtol=1e-7)


def test_map_without_orientation_default_needs_sidecar_orientation(tmp_path):
    path = write_log(tmp_path / "log.csv", rig_table(5), SIDECAR)
    cmap = load_column_map().model_copy(update={"defaults": load_column_map().defaults.model_copy(
        update={"orientation_deg": None})})
    with pytest.raises(CsvFormatError, match="orientation_deg"):
        read_csv_run(path, cmap)


def bad_map(tmp_path: Path, change) -> Path:
    data = yaml.safe_load(DEFAULT_COLUMN_MAP.read_text())
    change(data)
    path = tmp_path / "bad_map.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.mark.parametrize(("change", "words"), [
    (lambda d: d["columns"].update(forse=[1, 2, 3]),
     ["'columns.forse' is not allowed", "keys: angles, force, in_contact"]),
    (lambda d: d.update(colour="red"), ["'colour' is not allowed"]),
    (lambda d: d["units"].update(angles="grad"), ["'units.angles'", "'deg' or 'rad'"]),
    (lambda d: d["columns"].update(force=[1, 2]), ["'columns.force.2': Field required"]),
    (lambda d: d["columns"]["temperature"].pop(), ["temperature must name one column per pressure"]),
    (lambda d: d.update(header=False), ["header is false"]),
    (lambda d: d["units"].update(pressure_scale=-1), ["'units.pressure_scale'"]),
    (lambda d: d.pop("columns"), ["'columns'", "Field required"]),
])
def test_bad_column_map_names_file_and_key(tmp_path, change, words):
    path = bad_map(tmp_path, change)
    with pytest.raises(AnytipError) as info:
        load_column_map(path)
    msg = str(info.value)
    assert str(path) in msg
    for word in words:
        assert word in msg, msg


def test_map_names_a_column_the_log_lacks(tmp_path, log):
    path = bad_map(tmp_path, lambda d: d["columns"].update(time="t_s"))
    with pytest.raises(CsvFormatError, match="columns.time: no header column named 't_s'"):
        read_csv_run(log, path)


def test_map_index_out_of_range(tmp_path, log):
    path = bad_map(tmp_path, lambda d: d["columns"].update(time=40))
    with pytest.raises(CsvFormatError, match="column 40 out of range"):
        read_csv_run(log, path)


def test_100k_rows_import_whole_and_in_order(tmp_path):
    n, block = 100_000, rig_table(1000)
    rest = [",".join(f"{v:.10g}" for v in row[1:]) for row in block]
    path = tmp_path / "big.csv"
    path.write_text(",".join(HEADER) + "\n"
                    + "".join(f"{i / 200:.3f},{rest[i % 1000]}\n" for i in range(n)))
    path.with_suffix(".json").write_text(json.dumps(SIDECAR))
    run = read_csv_run(path)
    assert run.n_rows == n
    np.testing.assert_allclose(run.time, np.arange(n) / 200, atol=5e-4)
    blocks = run.pressure.reshape(n // 1000, 1000, -1)  # every row kept, in order: the block repeats
    assert np.array_equal(blocks, np.broadcast_to(blocks[0], blocks.shape))


def test_registry_imports_csv_and_exports_interchange(tmp_path):
    folder = tmp_path / "logs"
    folder.mkdir()
    write_log(folder / "a.csv", rig_table(100, seed=1), SIDECAR)
    write_log(folder / "b.csv", rig_table(100, seed=2), {**SIDECAR, "orientation_deg": -45})
    reg = Registry(tmp_path / "reg")
    report = reg.import_paths([folder])
    assert [r.run_id for r in report.added] == [
        "FT-0042_o0_20240602T093000Z", "FT-0042_o-45_20240602T093000Z"]
    assert all(r.source == "rig" for r in report.added)
    exported = reg.export("FT-0042", tmp_path / "out")
    assert {read_run(p).content_hash() for p in exported} == {r.sha256 for r in report.added}
    assert reg.import_paths([folder]).added == []


def test_registry_lists_every_bad_csv(tmp_path):
    folder = tmp_path / "logs"
    folder.mkdir()
    write_log(folder / "good.csv", rig_table(20), SIDECAR)
    bad_cell = write_log(folder / "bad_cell.csv", rig_table(20), SIDECAR)
    set_cell(bad_cell, 4, 2, "??")
    no_sidecar = write_log(folder / "lonely.csv", rig_table(20))
    reg = Registry(tmp_path / "reg")
    with pytest.raises(AnytipError) as info:
        reg.import_paths([folder])
    msg = str(info.value)
    assert f"{bad_cell}, line 4, column 2 (Fy)" in msg and str(no_sidecar) in msg
    assert "good.csv" not in msg and reg.list_runs() == []


EDGE_MAP = builtin("configs") / "csv" / "edge4_example.yaml"


def edge_log(path: Path, n: int = 50, x_col: str = "x") -> Path:
    """A 4-barometer edge sensor's log as the example map describes: hPa, mm, ms."""
    g = np.random.default_rng(3)
    rows = ["Sensor_0,Sensor_1,Sensor_2,Sensor_3," + x_col + ",z,time"]
    for i in range(n):
        p = 1000 + g.standard_normal(4)
        rows.append(",".join(f"{v:.4f}" for v in [*p, 40 * i / n, 2.5 * (i % 5) / 5, 10.0 * i]))
    path.write_text("\n".join(rows) + "\n")
    sidecar = {"sensor_id": "EDGE-7", "created": "2025-02-01T10:00:00Z"}
    path.with_suffix(".json").write_text(json.dumps(sidecar))
    return path


def test_named_targets_make_a_v2_run(tmp_path):
    path = edge_log(tmp_path / "edge.csv")
    run = read_csv_run(path, EDGE_MAP)
    assert run.format_version == 2 and run.n_channels == 4 and run.sensor_model == "edge-4baro"
    assert {n: (t.unit, t.components) for n, t in run.targets.items()} == {
        "position": ("m", ("x",)), "depth": ("m", ("z",))}
    np.testing.assert_allclose(run.target("position")[:, 0], 0.04 * np.arange(50) / 50, rtol=1e-6)
    np.testing.assert_allclose(run.time, 0.01 * np.arange(50))
    assert 0.9e5 < run.pressure.mean() < 1.1e5
    reg = Registry(tmp_path / "reg")
    reg.import_paths([path], column_map=EDGE_MAP)
    (out,) = reg.export("EDGE-7", tmp_path / "out")
    assert read_run(out).content_hash() == run.content_hash()


def test_a_named_target_column_that_is_missing_is_named(tmp_path):
    path = edge_log(tmp_path / "edge.csv", x_col="pos")
    with pytest.raises(CsvFormatError, match=r"edge\.csv.*targets\.position.*'x'"):
        read_csv_run(path, EDGE_MAP)


@pytest.mark.parametrize(("columns", "words"), [
    ({"force": [1, 2, 3]}, ["force and angles", "or targets"]),
    ({"targets": {}}, ["targets"]),
    ({"targets": {"d": {"columns": [4], "unit": "m", "components": ["a", "b"]}}}, ["components names 2"]),
    ({"targets": {"d": {"columns": [4], "unit": "m", "scale": 0}}}, ["scale"]),
    ({"targets": {"d": {"columns": [4], "unit": "m"}}, "force": [1, 2, 3], "angles": [5, 6]}, ["not both"]),
])
def test_bad_label_columns_are_refused(tmp_path, columns, words):
    spec = {"name": "x", "header": False, "columns": {"time": 0, "pressure": [1, 2], **columns}}
    path = tmp_path / "map.yaml"
    path.write_text(yaml.safe_dump(spec))
    with pytest.raises(AnytipError) as info:
        load_column_map(path)
    for word in words:
        assert word in str(info.value), str(info.value)
