"""The deployed sensors' firmware struct: import of the six reference nets, exact round trip, export."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from anytip.deploy import firmware as fw
from anytip.deploy.export import export_model
from anytip.deploy.net import deploy_net, model_predict
from anytip.errors import AnytipError
from anytip.models.io import load_models, save_models
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from test_deploy_helpers import save_baseline, synthetic_x

# the six networks deployed on real sensors (vendored from shared/reference/ so any clone runs these)
REFERENCE = Path(__file__).resolve().parent / "fixtures" / "deployed_nets.json"


@pytest.fixture(scope="module")
def nets():
    return fw.read_firmware_json(REFERENCE)


def in_range(net: dict, rows: int = 400, seed: int = 0) -> np.ndarray:
    lo, hi = net["minims"][fw.N_OUT:], net["maxims"][fw.N_OUT:]
    return lo + (hi - lo) * np.random.default_rng(seed).uniform(0, 1, (rows, 8))


def test_six_nets_round_trip_exactly_through_model_files(nets, tmp_path):
    assert len(nets) == 6
    path = save_models(tmp_path / "m.safetensors", *_loaded_parts(fw.import_firmware(nets)))
    loaded = load_models(path)
    for i, (name, net) in enumerate(nets.items()):
        back = fw.to_firmware(loaded, i, deploy_net(loaded, i), in_range(net))
        for key in net:
            assert back[key].tolist() == net[key].tolist(), (name, key)


def _loaded_parts(loaded):
    return loaded.model, loaded.in_scaler, loaded.out_scaler, loaded.meta


def test_json_file_round_trip_is_exact(nets, tmp_path):
    loaded = fw.import_firmware(nets)
    out = {n: fw.to_firmware(loaded, i, deploy_net(loaded, i), in_range(nets[n])) for i, n in enumerate(nets)}
    path = fw.write_firmware_json(tmp_path / "fw.json", out, fw.DESCRIPTION)
    original = json.loads(REFERENCE.read_text())["units"]
    assert json.loads(path.read_text())["units"] == original


def test_imported_model_matches_direct_evaluation_of_the_json(nets):
    loaded = fw.import_firmware(nets)
    for i, (name, net) in enumerate(nets.items()):
        x = in_range(net, seed=i)
        direct = fw.to_rad(fw.firmware_forward(net, x))
        scale = deploy_net(loaded, i).out_scale
        assert (np.abs(model_predict(loaded, i, x) - direct).max(0) / scale).max() <= 1e-5, name
        assert (np.abs(model_predict(loaded, i, x, double=False) - direct).max(0) / scale).max() <= 1e-5, name


def test_bad_json_names_file_and_key(tmp_path, nets):
    doc = json.loads(REFERENCE.read_text())
    del doc["units"]["sensor28"]["w3"]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(AnytipError, match="sensor28.*'w3'"):
        fw.read_firmware_json(bad)


def test_model_with_negative_outputs_is_rescaled_not_clipped(tmp_path):
    path = save_baseline(tmp_path)
    loaded = load_models(path)
    x = synthetic_x()
    y = model_predict(loaded, 0, x)
    assert (y < 0).any()  # a naive min-max scaling at 0 would clip these
    r = export_model(path, "firmware", tmp_path / "fw", unit="U0")
    assert r["passed"] and r["output_relu"]["clipped_outputs_on_reference"] == 0
    back = fw.read_firmware_json(tmp_path / "fw" / "firmware.json")["U0"]
    assert np.all(back["minims"][:5] < y.min(0) * np.array([1, 1, 1, 180 / np.pi, 180 / np.pi]))
    direct = fw.to_rad(fw.firmware_forward(back, x))
    assert (np.abs(direct - y).max(0) / deploy_net(loaded, 0).out_scale).max() <= 1e-5


def test_other_sizes_are_refused(tmp_path):
    cfg = MLPConfig(sizes=(8, 16, 5))
    path = save_models(tmp_path / "s.safetensors", BatchedMLP(1, cfg), Scaler.identity(1, 8),
                       Scaler.identity(1, 5), {"unit_ids": ["S"]})
    with pytest.raises(AnytipError, match="firmware struct holds an MLP of sizes"):
        export_model(path, "firmware", tmp_path / "out")


def test_cli_imports_a_firmware_net_and_exports_it_back(tmp_path):
    from anytip.cli import main

    assert main(["export", str(REFERENCE), "--unit", "sensorC3", "--format", "model", "--out",
                 str(tmp_path / "m"), "--registry", str(tmp_path / "none")]) == 0
    assert main(["export", str(tmp_path / "m" / "model.safetensors"), "--format", "firmware",
                 "--out", str(tmp_path / "fw"), "--registry", str(tmp_path / "none")]) == 0
    units = json.loads((tmp_path / "fw" / "firmware.json").read_text())["units"]
    assert units == {"sensorC3": json.loads(REFERENCE.read_text())["units"]["sensorC3"]}
