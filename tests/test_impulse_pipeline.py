"""The impulse_ratio spec end to end, on small options: report, figures and metrics rows."""

import json
from pathlib import Path

import pytest

from anytip.analysis.impulse import NOMINAL, collision_impulse_ratio
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.rundir import METRIC_KEYS
from anytip.runner import run_experiment

SPEC = Path(__file__).resolve().parents[1] / "experiments" / "impulse_ratio.yaml"
SMALL = ["seeds=[0]", "training.epochs=1", "options.map_points=9", "options.check_points=2",
         "options.latency.presses=6", "options.latency.protocols=[quick]", "options.v0_values=[0.1, 0.5]"]


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("impulse")
    return run_experiment(SPEC, Registry(root / "registry"), root / "out", SMALL, progress=False)


def test_report_figures_and_rows(run_dir):
    report = (run_dir / "report.md").read_text()
    for part in ("Nominal eta = 0.3632", "max |eta closed form - eta numeric|", "fig5_latency_stiffness.png",
                 "fig5_latency_v0.png", "Is eta invariant to the approach speed?", "filtfilt",
                 "End-to-end latency of the device output", "paper's 7 ms", "estimate"):
        assert part in report, part
    for png in ("fig5_latency_stiffness.png", "fig5_latency_v0.png", "collision_trace.png",
                "latency_stream.png"):
        assert (run_dir / png).stat().st_size > 10_000
    rows = json.loads((run_dir / "metrics.json").read_text())["results"]
    assert all(k in r for r in rows for k in METRIC_KEYS)
    by = {r["method"]: r for r in rows}
    assert by["impulse:nominal"]["eta"] == pytest.approx(collision_impulse_ratio(**NOMINAL))
    assert by["impulse:closed_vs_numeric"]["max_abs_diff"] < 1e-8
    assert all(r["max_abs_diff"] < 1e-10 for r in rows if r["method"] == "filter:zero_phase_vs_filtfilt")
    device = by["latency:device"]
    assert 0.0 < device["latency_s"] < 0.02 and device["unit"] != "-" and device["calib_samples"] > 0
    assert by["latency:device + causal MA 15"]["latency_s"] > device["latency_s"] + 0.03
    assert abs(by["latency:physics:memoryless"]["latency_s"]) < 1e-3


def test_bad_option_names_the_key(tmp_path):
    with pytest.raises(AnytipError, match=r"options.*latency\.presess.*allowed keys.*presses"):
        run_experiment(SPEC, Registry(tmp_path / "registry"), tmp_path / "out",
                       ["options.latency.presess=3"], progress=False)
    with pytest.raises(AnytipError, match=r"options: key 'nominal.k'.*greater than 0 \(got -1\)"):
        run_experiment(SPEC, Registry(tmp_path / "registry"), tmp_path / "out2",
                       ["options.nominal.k=-1"], progress=False)
    with pytest.raises(AnytipError, match=r"options.map_latency_ms: need 0 <= low < high.*got \[5.0, 1.0\]"):
        run_experiment(SPEC, Registry(tmp_path / "registry"), tmp_path / "out3",
                       ["options.map_latency_ms=[5, 1]"], progress=False)
