"""The command line end to end: simulate, list, export, import elsewhere, verify, remove."""

import json
import subprocess
import sys

import pytest

from anytip.cli import main
from anytip.data.registry import Registry


def run_cli(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_data_verbs_round_trip(tmp_path, capsys):
    reg, other, out = str(tmp_path / "reg"), str(tmp_path / "other"), tmp_path / "exported"
    code, text, _ = run_cli(capsys, "data", "simulate", "--units", "2", "--seed", "4",
                            "--protocols", "short", "--registry", reg)
    assert code == 0 and "6 runs added" in text
    code, text, _ = run_cli(capsys, "data", "simulate", "--units", "2", "--seed", "4",
                            "--protocols", "short", "--registry", reg)
    assert "0 runs added, 6 unchanged" in text
    code, text, _ = run_cli(capsys, "data", "list", "--json", "--registry", reg)
    rows = [json.loads(line) for line in text.splitlines()]
    assert len(rows) == 6 and {r["unit"] for r in rows} == {"SIM4-000", "SIM4-001"}
    code, text, _ = run_cli(capsys, "data", "list", "--registry", reg)
    assert ("sensor model fingertip-8baro-r10: 8 pressure channels and the targets "
            "angles [rad] (theta, phi), force [N] (fx, fy, fz) (2 units)") in text
    assert run_cli(capsys, "data", "export", "SIM4-001", "--out", str(out), "--registry", reg)[0] == 0
    assert len(list(out.glob("*.h5"))) == 3
    code, text, _ = run_cli(capsys, "data", "import", str(out), "--registry", other)
    assert code == 0 and "3 run(s) added" in text
    src, dst = Registry(reg), Registry(other)
    assert dst.content_hash() == src.content_hash([r.run_id for r in src.list_runs(unit="SIM4-001")])
    assert run_cli(capsys, "data", "verify", "--registry", other)[0] == 0
    code, text, _ = run_cli(capsys, "data", "remove", "SIM4-001", "--registry", reg)
    assert code == 0 and "removed 3 runs" in text
    assert len(Registry(reg).list_runs()) == 3


def test_verify_fails_on_missing_payload(tmp_path, capsys):
    reg = str(tmp_path / "reg")
    run_cli(capsys, "data", "simulate", "--units", "1", "--protocols", "short", "--registry", reg)
    registry = Registry(reg)
    registry.payload_path(registry.list_runs()[0].run_id).unlink()
    code, text, _ = run_cli(capsys, "data", "verify", "--registry", reg)
    assert code == 1 and "payload missing" in text


def test_errors_are_one_line_naming_the_file(tmp_path, capsys):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not hdf5 at all")
    code, _, err = run_cli(capsys, "data", "import", str(bad), "--registry", str(tmp_path / "reg"))
    assert code == 2 and str(bad) in err and "Traceback" not in err
    spec = tmp_path / "exp.yaml"
    spec.write_text("pipeline: baseline\nbogus: 1\n")
    code, _, err = run_cli(capsys, "run", str(spec), "--registry", str(tmp_path / "reg"))
    assert code == 2 and "bogus" in err and str(spec) in err


def test_console_script_and_env_registry(tmp_path):
    env = {"ANYTIP_REGISTRY": str(tmp_path / "envreg"), "PATH": "/usr/bin:/bin"}
    exe = [sys.executable, "-m", "anytip.cli"]
    done = subprocess.run([*exe, "data", "simulate", "--units", "1", "--protocols", "short"],
                          env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "envreg" / "catalog.sqlite").is_file()


@pytest.mark.parametrize("verb", ["simulate", "import", "export", "list", "verify", "protocol", "remove"])
def test_every_data_verb_has_help(verb, capsys):
    with pytest.raises(SystemExit) as e:
        main(["data", verb, "--help"])
    assert e.value.code == 0 and "--registry" in capsys.readouterr().out


def test_a_long_run_says_what_it_has_done_on_stderr(capsys, tmp_path):
    """`Context.say`: one stderr line with the spec's name and the seconds since the run began,
    also without progress bars (a log file); nothing when told not to narrate, nothing on stdout."""
    import torch

    from anytip.config import load_spec
    from anytip.pipelines.common import Context

    spec = load_spec("experiments/cross_sensor.yaml")
    Context(spec, Registry(tmp_path / "r"), tmp_path, torch.device("cpu"), False).say("references trained")
    Context(spec, Registry(tmp_path / "r"), tmp_path, torch.device("cpu"), narrate=False).say("not shown")
    out = capsys.readouterr()
    assert out.out == "" and out.err.startswith("[cross_sensor +0 s] references trained")
    assert "not shown" not in out.err


def test_data_protocol_marks_and_clears(tmp_path, capsys):
    from anytip.data.runfile import write_run
    from run_factory import make_run

    reg = str(tmp_path / "reg")
    files = [write_run(make_run("FT-1", o, source="rig"), tmp_path / f"{o}.h5") for o in (0, -45)]
    code, text, _ = run_cli(capsys, "data", "import", str(files[0]), "--protocol", "plan120",
                            "--registry", reg)
    assert code == 0 and "1 run(s) added, 0 unchanged, marked as protocol 'plan120'" in text
    run_cli(capsys, "data", "import", str(files[1]), "--registry", reg)
    code, text, _ = run_cli(capsys, "data", "protocol", "FT-1_o-45_20240501T120000Z", "retest",
                            "--registry", reg)
    assert code == 0 and text == "FT-1_o-45_20240501T120000Z: retest\n"
    code, text, _ = run_cli(capsys, "data", "list", "--registry", reg)
    assert "retest *" in text and "plan120 *" in text and "* protocol marked in the registry" in text
    code, text, _ = run_cli(capsys, "data", "protocol", "FT-1", "--clear", "--registry", reg)
    assert code == 0 and text.count(": -\n") == 2
    for args in (("FT-1",), ("FT-1", "retest", "--clear")):
        code, _, err = run_cli(capsys, "data", "protocol", *args, "--registry", reg)
        assert code == 2 and "give a protocol name or --clear, not both" in err


def test_interval_half_widths_read_in_the_units_a_spec_only_run_file_declares(tmp_path, capsys):
    """A sensor model's output units come from the run files a lab wrote from the format spec alone (an
    edge sensor's position and depth in m), not from the fingertip's N and rad."""
    from anytip.cli import _output_units, _print_intervals
    from test_runfile_v2 import edge_file

    registry = Registry(tmp_path / "reg")
    registry.import_paths([edge_file(tmp_path / "edge.h5")])
    units = _output_units(registry, "EDGE-01")
    assert units == {"x": "m", "z": "m"}
    assert _output_units(registry, "NO-SUCH-UNIT") == {}
    bands = {"level": 0.9, "folds": None, "rows": 30, "halfwidth": {"x": 0.0012, "z": 0.0004}}
    _print_intervals(bands, units)
    said = capsys.readouterr().out
    assert "x +-0.0012 m, z +-0.0004 m" in said and " N" not in said and "rad" not in said
