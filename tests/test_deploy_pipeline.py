"""The deploy experiment: every format and peer measured in one run, one metrics row each."""

from __future__ import annotations

import json

import pytest
import yaml

from anytip.deploy import embedded
from anytip.deploy import quantize as quantize_mod
from anytip.errors import AnytipError
from anytip.runner import run_experiment
from test_deploy_helpers import save_baseline


def spec(tmp_path, options) -> str:
    path = tmp_path / "deploy.yaml"
    path.write_text(yaml.safe_dump({"pipeline": "deploy", "description": "test", "threads": 1,
                                    "options": options}))
    return str(path)


def test_deploy_run_writes_rows_and_report(small_registry, tmp_path, monkeypatch):
    monkeypatch.setattr(quantize_mod, "REFINE", ((0, 1, 200),))
    model = save_baseline(tmp_path, n=1)
    opts = {"models": [{"name": "tiny", "path": str(model)}], "rows": 400,
            "calibrate": [{"name": "folded", "shared": "none.safetensors", "unit": "NOT-IN-REGISTRY"}]}
    monkeypatch.chdir(tmp_path)  # a relative run directory, as `--out reports/deploy` gives
    run_dir = run_experiment(spec(tmp_path, opts), small_registry, out="run", progress=False)
    rows = json.loads((run_dir / "metrics.json").read_text())["results"]
    methods = {r["method"] for r in rows}
    assert methods == {"anytip_onnx", "anytip_c", "anytip_c_int8", "anytip_firmware", "emlearn",
                       "emx_onnx_cgen"}
    by = {r["method"]: r for r in rows}
    assert by["anytip_c"]["passed"] and by["anytip_c"]["max_rel_err"] <= 1e-5
    report = (run_dir / "report.md").read_text()
    assert "## tiny" in report and "NOT-IN-REGISTRY" in report
    if embedded.emulator_missing() is None:
        for peer in ("emlearn", "emx_onnx_cgen"):
            if by[peer]["instructions"] is not None:
                assert by["anytip_c"]["instructions"] < by[peer]["instructions"]
                assert by["anytip_c"]["ram_bytes"] <= by[peer]["ram_bytes"]
    assert (run_dir / "exports" / "tiny" / "c" / "verification.json").exists()


def test_bad_options_name_the_key(small_registry, tmp_path):
    with pytest.raises(AnytipError, match="formats or peers"):
        run_experiment(spec(tmp_path, {"models": [{"name": "a", "path": "x"}], "formats": ["tflite"]}),
                       small_registry, out=tmp_path / "r", progress=False)
    with pytest.raises(AnytipError, match="options"):
        run_experiment(spec(tmp_path, {"modles": []}), small_registry, out=tmp_path / "r2", progress=False)


def test_hand_written_reading_survives_a_rerun(tmp_path):
    """Any pipeline's report keeps the run directory's hand-written reading.md after its own text."""
    from anytip.report.writer import READING, Report

    Report(tmp_path).add("# Title", "generated").write()
    assert (tmp_path / "report.md").read_text() == "# Title\ngenerated\n"
    (tmp_path / READING).write_text("## Reading\n\nThe figures mean this.\n")
    Report(tmp_path).add("# Title", "generated again").write()
    text = (tmp_path / "report.md").read_text()
    assert text.startswith("# Title\ngenerated again\n")
    assert text.endswith("## Reading\n\nThe figures mean this.\n") and "check it against" in text
