"""Inputs from registries and users we did not write: crafted run files, tampered payloads, bad specs
and command lines. Every refusal is one line naming the file, key or value, exit status 2, and
nothing written. Run files here are made with raw h5py from the format spec alone."""

from __future__ import annotations

import json
import os
import sqlite3
import stat
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from anytip.cli import main
from anytip.config import load_spec
from anytip.data.arrays import load_arrays
from anytip.data.registry import Registry
from anytip.data.runfile import RunFormatError, read_run, write_run
from anytip.errors import AnytipError
from run_factory import make_run

REPO = Path(__file__).resolve().parents[1]
TINY = ["training.epochs=1", "training.batch_size=64"]
SHORT = ["--set", "data.protocol=short"]
TINY_SET = [a for s in TINY for a in ("--set", s)]  # the small registry holds short-protocol runs


def spec_file(path: Path, name: str = "spec.yaml", text: str = "pipeline: baseline\n") -> Path:
    f = path / name
    f.write_text(text)
    return f


def write_spec_run(path: Path, n: int = 400, channels: int = 8, **attrs) -> Path:
    """A v1 run file written with raw h5py from CALIBRATION_FORMAT.md alone (no anytip writer)."""
    rng = np.random.default_rng(0)
    rest = np.arange(n) < 150  # 0.75 s at rest first
    force = np.where(rest[:, None], 0.0, rng.normal(0, 1, (n, 3)) * [2, 2, 6] - [0, 0, 8])
    with h5py.File(path, "w") as f:
        base = {"format": "calibration_run", "format_version": 1, "sensor_id": "LAB-0001",
                "sensor_model": "fingertip-8baro-r10", "orientation_deg": 0.0, "sample_rate_hz": 200.0,
                "source": "rig", "created": "2025-03-01T09:00:00Z"}
        for k, v in {**base, **attrs}.items():
            f.attrs[k] = v
        f["time"] = np.arange(n) / 200.0
        f["pressure"] = (1e5 + rng.normal(0, 30, (n, channels))).astype(np.float32)
        f["force"] = force.astype(np.float32)
        f["angles"] = rng.uniform(-0.5, 0.5, (n, 2)).astype(np.float32)
    return path


def cli(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, *args: str, names: str) -> str:
    """Run the CLI, expect exit 2 and one stderr line naming `names`."""
    code, _, err = cli(capsys, *args)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) >= 1 and "Traceback" not in err and names in err, err
    return err


# ---- security: a run file is read from itself alone --------------------------------------------


def test_external_raw_storage_is_refused_and_never_read(tmp_path):
    secret = tmp_path / "secret.bin"
    secret.write_bytes(np.arange(64 * 8, dtype=np.float32).tobytes())
    path = write_spec_run(tmp_path / "ext.h5", n=64)
    with h5py.File(path, "a") as f:
        del f["pressure"]
        f.create_dataset("pressure", shape=(64, 8), dtype=np.float32, external=[(str(secret), 0, 64 * 8 * 4)])
    with pytest.raises(RunFormatError, match="external raw storage"):
        read_run(path)
    reg = Registry(tmp_path / "reg")
    with pytest.raises(AnytipError, match="external raw storage"):
        reg.import_paths(path)
    assert reg.list_runs() == []


@pytest.mark.parametrize("kind", ["external", "soft"])
def test_links_are_refused(tmp_path, kind):
    other = write_spec_run(tmp_path / "other.h5")
    path = write_spec_run(tmp_path / "linked.h5")
    with h5py.File(path, "a") as f:
        del f["force"]
        f["elsewhere/force"] = np.zeros((400, 3), np.float32)
        external = h5py.ExternalLink(str(other), "/force")
        f["force"] = external if kind == "external" else h5py.SoftLink("/elsewhere/force")
    with pytest.raises(RunFormatError, match=f"{kind} link"):
        read_run(path)


def test_virtual_datasets_are_refused(tmp_path):
    src = write_spec_run(tmp_path / "src.h5")
    path = write_spec_run(tmp_path / "vds.h5")
    layout = h5py.VirtualLayout(shape=(400, 2), dtype=np.float32)
    layout[:] = h5py.VirtualSource(str(src), "angles", shape=(400, 2))
    with h5py.File(path, "a") as f:
        del f["angles"]
        f.create_virtual_dataset("angles", layout)
    with pytest.raises(RunFormatError, match="virtual dataset"):
        read_run(path)


def test_a_tampered_payload_never_trains(small_registry, capsys, tmp_path):
    rec = small_registry.list_runs()[0]
    path = small_registry.payload_path(rec.run_id)
    with h5py.File(path, "a") as f:  # a valid file with other values: only the hash can tell
        f["force"][0] = f["force"][0] + 1.0
    with pytest.raises(AnytipError, match=f"{rec.run_id}.*changed since import"):
        load_arrays(small_registry, [rec])
    spec = REPO / "experiments" / "baseline.yaml"
    out = tmp_path / "run"
    err = refused(capsys, "run", str(spec), "--registry", str(small_registry.root), "--out", str(out),
                  *[a for s in TINY for a in ("--set", s)], *SHORT, names="changed since import")
    assert rec.run_id in err and not (out / "metrics.json").exists()


def test_secrets_stay_out_of_files_and_messages(small_registry, tmp_path, capsys):
    from anytip.validation import mask_secrets

    url = "postgresql://lab:hunter2@127.0.0.1:1/optuna"
    assert mask_secrets(f"x {url} y") == "x postgresql://lab:***@127.0.0.1:1/optuna y"
    out = tmp_path / "s"
    err = refused(capsys, "search", str(REPO / "experiments" / "search.yaml"), "--registry",
                  str(small_registry.root), "--out", str(out), "--storage", url,
                  "--set", "options.n_trials=1", "--set", "options.n_search_units=2",
                  "--set", "options.n_test_units=2", *TINY_SET, *SHORT, names="options.storage")
    assert "hunter2" not in err
    for f in out.rglob("*") if out.exists() else []:
        assert "hunter2" not in f.read_text(errors="ignore"), f


def test_spec_paths_cannot_escape(tmp_path):
    """A block named by `use:` is read from configs/<kind>/ only; a spec name is one directory."""
    project = tmp_path / "project"
    (project / "configs" / "models").mkdir(parents=True)
    (tmp_path / "outside.yaml").write_text("sizes: [8, 5]\n")  # a valid model block outside configs/
    spec = spec_file(project, text="pipeline: baseline\nmodel: {use: ../../../outside}\n")
    with pytest.raises(AnytipError, match="model.use"):
        load_spec(spec)
    with pytest.raises(AnytipError, match="name"):
        load_spec(spec_file(project, text="name: ../../escape\npipeline: baseline\n"))


def test_an_edited_catalog_path_never_deletes_a_payload(tmp_path, caplog):
    reg = Registry(tmp_path / "reg")
    rec = reg.add_runs([make_run("FT-1")])[0]
    payload = reg.payload_path(rec.run_id)
    with sqlite3.connect(reg.db_path) as conn:
        conn.execute("UPDATE runs SET path = 'runs/FT-1/elsewhere.h5' WHERE run_id = ?", (rec.run_id,))
    stray = reg.root / "runs" / "FT-1" / "stray.h5"
    stray.write_bytes(b"not named by any row")
    reg.add_runs([make_run("FT-2")])  # an import sweeps orphans
    assert payload.is_file() and not stray.exists()
    assert any("stray.h5" in r.getMessage() for r in caplog.records)


# ---- bad input: clear errors, exit 2, nothing written --------------------------------------------


@pytest.mark.parametrize("created", ["0001-01-01T00:00:00+05:00", "9999-12-31T23:59:59-05:00", "yesterday"])
def test_out_of_range_or_invalid_created_is_refused(tmp_path, capsys, created):
    path = write_spec_run(tmp_path / "run.h5", created=created)
    refused(capsys, "data", "import", str(path), "--registry", str(tmp_path / "reg"), names="created")
    assert Registry(tmp_path / "reg").list_runs() == []


def test_a_csv_sidecar_with_an_out_of_range_date_is_refused(tmp_path, capsys):
    cmap = REPO / "configs" / "csv" / "rig34.yaml"
    log = tmp_path / "log.csv"
    log.write_text("x\n1\n")
    sidecar = {"sensor_id": "A-1", "created": "0001-01-01T00:00:00+05:00"}
    (tmp_path / "log.json").write_text(json.dumps(sidecar))
    code, _, err = cli(capsys, "data", "import", str(log), "--csv-map", str(cmap),
                       "--registry", str(tmp_path / "r"))
    assert code == 2 and "Traceback" not in err and "log" in err


def test_a_huge_declared_shape_is_refused_before_reading(tmp_path):
    path = tmp_path / "huge.h5"
    with h5py.File(path, "w") as f:
        for k, v in {"format": "calibration_run", "format_version": 1, "sensor_id": "H-1",
                     "sensor_model": "m", "orientation_deg": 0.0, "sample_rate_hz": 200.0,
                     "source": "rig", "created": "2025-01-01T00:00:00Z"}.items():
            f.attrs[k] = v
        n = 10**11
        for name, shape, dt in (("time", (n,), "f8"), ("pressure", (n, 8), "f4"), ("force", (n, 3), "f4"),
                                ("angles", (n, 2), "f4")):
            f.create_dataset(name, shape=shape, dtype=dt, chunks=True, compression="gzip")
    assert path.stat().st_size < 10**6
    with pytest.raises(RunFormatError, match="more than the .* of memory"):
        read_run(path)


def test_an_infinite_duration_is_refused(tmp_path):
    path = write_spec_run(tmp_path / "slow.h5", sample_rate_hz=1e-320)
    with pytest.raises(RunFormatError, match="sample_rate_hz"):
        read_run(path)


@pytest.mark.parametrize("value", [0.0, -40.0, 2.0**24, 3.4e38])
def test_a_pressure_no_barometer_reads_is_refused_on_import(tmp_path, capsys, value):
    """A tared log, a failed read's sentinel: outside (0, 2**24) Pa, named by row and column."""
    path = write_spec_run(tmp_path / "sentinel.h5")
    with h5py.File(path, "r+") as f:
        f["pressure"][210, 5] = value
    err = refused(capsys, "--registry", str(tmp_path / "reg"), "data", "import", str(path),
                  names="sentinel.h5: dataset 'pressure' holds")
    assert "row 210, column 5" in err
    assert not (tmp_path / "reg").exists() or not Registry(tmp_path / "reg").list_runs()


def test_a_pressure_inside_the_range_is_read(tmp_path):
    path = write_spec_run(tmp_path / "edge.h5")
    with h5py.File(path, "r+") as f:
        f["pressure"][210, 5] = np.nextafter(np.float32(2.0**24), np.float32(0))
        f["pressure"][211, 5] = np.float32(1e-3)
    assert read_run(path).n_rows == 400


@pytest.mark.parametrize(("override", "names"), [
    ("seed=[unclosed", "--set"), ("seeds=[-1]", "seeds"), ("training.epochs=true", "training.epochs"),
    ("training.lr=.inf", "training.lr"), ("training.lr=.nan", "training.lr"),
    ("training.batch_size=100000000000", "training.batch_size"), ("threads=100000", "threads"),
    ("training.epochs=10000000", "training.epochs"), ("model.sizes=[8,100000,5]", "model.sizes"),
    ("options.bogus=1", "options"), ("epochs=3", "epochs"), ("seed='3'", "seed"),
])
def test_bad_spec_values_are_refused_before_any_work(small_registry, tmp_path, capsys, override, names):
    out = tmp_path / "run"
    refused(capsys, "run", str(REPO / "experiments" / "baseline.yaml"), "--registry",
            str(small_registry.root), "--out", str(out), "--set", override, names=names)
    assert not out.exists()


def test_yaml_aliases_are_refused(tmp_path):
    text = "pipeline: baseline\ndata: {protocol: &p short}\nrecipes: [*p, *p]\n"
    with pytest.raises(AnytipError, match="aliases"):
        load_spec(spec_file(tmp_path, text=text))


def test_yaml_1_2_floats_read_as_numbers(tmp_path):
    spec = load_spec(spec_file(tmp_path, text="pipeline: baseline\ntraining: {name: t, lr: 3e-3}\n"))
    assert spec.training.lr == 3e-3


@pytest.mark.parametrize("spec", ["baseline", "realism", "fleet_speed", "cross_sensor", "uncertainty",
                                  "search", "deploy", "impulse_ratio"])
def test_unknown_options_are_refused_by_every_pipeline(small_registry, tmp_path, capsys, spec):
    out = tmp_path / "run"
    refused(capsys, "run", str(REPO / "experiments" / f"{spec}.yaml"), "--registry", str(small_registry.root),
            "--out", str(out), "--set", "options.bogus=1", names="bogus")
    assert not out.exists()


def test_model_widths_must_match_the_sensor_model(small_registry, tmp_path, capsys):
    for sizes, names in (("[7,12,5]", "input width 7"), ("[8,12,4]", "output width 4")):
        refused(capsys, "run", str(REPO / "experiments" / "baseline.yaml"), "--registry",
                str(small_registry.root),
                "--out", str(tmp_path / "o"), "--set", f"model.sizes={sizes}", *SHORT, names=names)
    assert not (tmp_path / "o").exists()


def test_specs_needing_more_units_than_the_registry_holds_say_so_first(small_registry, tmp_path, capsys):
    refused(capsys, "run", str(REPO / "experiments" / "cross_sensor.yaml"), "--registry",
            str(small_registry.root), "--out", str(tmp_path / "o"), "--set", "splits.n_test_units=20",
            *SHORT, names="needs at least")
    assert not (tmp_path / "o").exists()


def test_a_garbage_catalog_is_refused(tmp_path, capsys):
    root = tmp_path / "reg"
    root.mkdir()
    (root / "catalog.sqlite").write_bytes(b"this is not a database" * 100)
    refused(capsys, "data", "list", "--registry", str(root), names="catalog.sqlite")


def test_export_out_onto_a_file_or_existing_runs(tmp_path, capsys):
    reg = Registry(tmp_path / "reg")
    reg.add_runs([make_run("FT-1")])
    target = tmp_path / "file"
    target.write_text("keep")
    refused(capsys, "data", "export", "FT-1", "--out", str(target), "--registry", str(reg.root),
            names=str(target))
    assert target.read_text() == "keep"
    out = tmp_path / "out"
    assert cli(capsys, "data", "export", "FT-1", "--out", str(out), "--registry", str(reg.root))[0] == 0
    refused(capsys, "data", "export", "FT-1", "--out", str(out), "--registry", str(reg.root), names="--force")
    again = cli(capsys, "data", "export", "FT-1", "--out", str(out), "--registry", str(reg.root), "--force")
    assert again[0] == 0


def test_a_layout_that_disagrees_with_its_sensor_model_is_refused(tmp_path, capsys):
    reg = tmp_path / "reg"
    ok = write_spec_run(tmp_path / "ok.h5")
    assert cli(capsys, "data", "import", str(ok), "--registry", str(reg))[0] == 0
    seven = write_spec_run(tmp_path / "seven.h5", channels=7, sensor_id="LAB-0002")
    err = refused(capsys, "data", "import", str(seven), "--registry", str(reg), names="seven.h5")
    assert "8 pressure channels" in err and "7" in err
    assert [r.unit for r in Registry(reg).list_runs()] == ["LAB-0001"]
    both = [write_spec_run(tmp_path / "a.h5", sensor_id="NEW-1", sensor_model="other"),
            write_spec_run(tmp_path / "b.h5", channels=4, sensor_id="NEW-2", sensor_model="other")]
    refused(capsys, "data", "import", *map(str, both), "--registry", str(reg), names="b.h5")


def test_every_json_the_project_writes_is_strict(tmp_path):
    from anytip.rundir import dumps_json

    text = dumps_json({"duration_s": float("inf"), "x": [float("nan"), 1.0], "n": np.float32(2)})
    assert json.loads(text, parse_constant=lambda c: pytest.fail(c)) == {"duration_s": None, "x": [None, 1.0],
                                                                        "n": 2.0}


def test_written_files_are_readable_like_any_other(tmp_path):
    from anytip.rundir import write_json

    old = os.umask(0o022)
    try:
        write_json(tmp_path / "m.json", {"a": 1})
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "m.json").stat().st_mode) == 0o644


@pytest.mark.parametrize("verb", [["data", "list"], ["data", "verify"], ["data", "export", "X", "--out", "o"],
                                  ["data", "remove", "X"]])
def test_a_mistyped_registry_is_not_created(tmp_path, capsys, verb):
    typo = tmp_path / "regsitry"
    refused(capsys, *verb, "--registry", str(typo), names="not a registry")
    assert not typo.exists()


def test_run_on_a_mistyped_registry_is_refused(tmp_path, capsys):
    typo = tmp_path / "regsitry"
    refused(capsys, "run", str(REPO / "experiments" / "baseline.yaml"), "--registry", str(typo),
            names="not a registry")
    assert not typo.exists()


def test_list_of_nothing_exits_non_zero(tmp_path, capsys):
    reg = Registry(tmp_path / "reg")
    reg.add_runs([make_run("FT-1")])
    code, _, err = cli(capsys, "data", "list", "--unit", "NOPE", "--registry", str(reg.root))
    assert code == 1 and "no runs of unit 'NOPE'" in err


def test_a_closed_pipe_ends_quietly(tmp_path):
    reg = Registry(tmp_path / "reg")
    # more output than a pipe buffer holds (64 KiB), so the writer meets the closed pipe
    reg.add_runs([make_run(f"FT-{i}", n=8, created=f"2024-05-01T12:{i // 60:02d}:{i % 60:02d}Z")
                  for i in range(400)])
    cmd = (f"{sys.executable} -c 'from anytip.cli import main; import sys; sys.exit(main())' "
           f"data list --json --registry {reg.root} | head -1")
    proc = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], capture_output=True, text=True, timeout=120)
    assert "Traceback" not in proc.stderr and "BrokenPipe" not in proc.stderr
    assert proc.stdout.count("\n") == 1


def test_a_finished_run_is_not_overwritten_without_force(small_registry, tmp_path, capsys):
    out = tmp_path / "run"
    args = ["run", str(REPO / "experiments" / "quickstart.yaml"), "--registry", str(small_registry.root),
            "--out", str(out), *[a for s in TINY for a in ("--set", s)], "--set", "data.protocol=short"]
    assert cli(capsys, *args)[0] == 0
    metrics = (out / "metrics.json").read_text()
    refused(capsys, *args, names="--force")
    assert (out / "metrics.json").read_text() == metrics
    assert cli(capsys, *args, "--force")[0] == 0
    for name in ("metrics.json", "provenance.json", "config.yaml"):
        assert stat.S_IMODE((out / name).stat().st_mode) & 0o044 == 0o044, name


def test_every_option_of_every_command_has_a_help_text():
    from anytip.cli import build_parser

    parser = build_parser()
    missing = []

    def walk(p, path):
        for action in p._actions:
            if action.__class__.__name__ == "_SubParsersAction":
                for name, sub in action.choices.items():
                    walk(sub, f"{path} {name}")
            elif action.option_strings or action.dest not in ("help",):
                if not action.help and action.dest != "help":
                    missing.append(f"{path} {action.dest}")
    walk(parser, "anytip")
    assert missing == []


def test_write_run_refuses_before_writing(tmp_path):
    run = make_run()
    run.created = "0001-01-01T00:00:00+05:00"
    with pytest.raises(RunFormatError):
        write_run(run, tmp_path / "x.h5")
    assert not (tmp_path / "x.h5").exists()


def test_uncertainty_runs_without_the_optional_temperature(small_registry, tmp_path):
    """A registry whose runs carry no `temperature` (optional in the format): the rest-drift
    detector is skipped with a line in the report, everything else runs."""
    from anytip.runner import run_experiment
    from test_uncertainty_fleet import TINY_SPEC

    bare = Registry(tmp_path / "bare")
    runs = []
    for rec in small_registry.list_runs():
        run = small_registry.open_run(rec.run_id)
        run.temperature = None
        runs.append(run)
    bare.add_runs(runs)
    spec = REPO / "experiments" / "uncertainty.yaml"
    overrides = [o for o in TINY_SPEC if not o.startswith("options.adapted")] + ["options.cv_folds=0",
                                                                                  "options.bootstrap=0"]
    out = run_experiment(spec, bare, out=tmp_path / "run", overrides=overrides, progress=False)
    rows = json.loads((out / "metrics.json").read_text())["results"]
    assert not any(str(r.get("method", "")).startswith("detect:rest_drift") for r in rows)
    assert any(r.get("method") == "detect:flatline" for r in rows)
    assert "rest-drift detector (`detect:rest_drift`) skipped" in (out / "report.md").read_text()


def test_the_package_does_not_pin_torch_exactly():
    """`pip install anytip` must keep a lab's own torch build; the exact CPU pin is the Makefile's."""
    import tomllib

    deps = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["dependencies"]
    torch_spec = next(d for d in deps if d.startswith("torch"))
    assert "==" not in torch_spec and ">=" in torch_spec
    assert "torch==2.13.0" in (REPO / "Makefile").read_text()


@pytest.mark.parametrize("fmt", ["onnx", "all"])
def test_model_export_onto_an_earlier_export_needs_force(tmp_path, capsys, fmt):
    from test_deploy_helpers import save_baseline

    model = save_baseline(tmp_path)
    out = tmp_path / "export"
    args = ["export", str(model), "--format", fmt, "--out", str(out), "--no-embedded", "--rows", "50",
            "--registry", str(tmp_path / "none")]
    assert cli(capsys, *args)[0] == 0
    first = sorted((p, p.stat().st_mtime_ns) for p in out.rglob("verification.json"))
    refused(capsys, *args, names="--force")
    assert sorted((p, p.stat().st_mtime_ns) for p in out.rglob("verification.json")) == first
    assert cli(capsys, *args, "--force")[0] == 0


def test_sidecars_and_budgets_read_yaml_like_specs(tmp_path):
    """Every YAML the project reads goes through one safe loader: aliases are refused in a CSV
    log's sidecar as in a spec."""
    from anytip.data.csv_import import _load_mapping

    sidecar = tmp_path / "log.yaml"
    sidecar.write_text("sensor_id: &s A-1\nnotes: *s\n")
    with pytest.raises(AnytipError, match="aliases"):
        _load_mapping(sidecar)
