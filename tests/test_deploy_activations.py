"""Hidden activations other than ReLU (leaky_relu, hardswish): ONNX and float32 C export them;
the int8 C and the firmware struct, whose arithmetic assumes ReLU, refuse them by name."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from anytip.deploy.c_export import write_c
from anytip.deploy.export import export_model
from anytip.deploy.native import run_c
from anytip.deploy.net import load_deploy_net, model_predict
from anytip.deploy.onnx_export import run_onnx, write_onnx
from anytip.errors import AnytipError
from anytip.models.mlp import MLPConfig
from test_deploy_helpers import save_baseline, synthetic_x

ACTIVATIONS = ["leaky_relu", "hardswish"]


@pytest.fixture(params=ACTIVATIONS)
def act_model(request, tmp_path):
    return request.param, save_baseline(tmp_path, config=MLPConfig(sizes=(8, 12, 64, 64, 5),
                                                                    activation=request.param))


def rel_err(y, ref, scale):
    return float((np.abs(y - ref).max(0) / scale).max())


def test_folded_net_follows_the_trained_model(act_model):
    act, path = act_model
    net, loaded, i = load_deploy_net(path)
    assert net.activation == act
    x = synthetic_x()
    assert rel_err(net.forward(x), model_predict(loaded, i, x), net.out_scale) < 1e-9
    relu_net, _, _ = load_deploy_net(save_baseline(path.parent / "relu"))
    assert relu_net.activation == "relu"


def test_onnx_exports_the_activation(act_model, tmp_path):
    act, path = act_model
    net, loaded, i = load_deploy_net(path)
    onnx_path = write_onnx(net, tmp_path)
    assert {"leaky_relu": b"LeakyRelu", "hardswish": b"HardSwish"}[act] in onnx_path.read_bytes()
    x = synthetic_x()
    assert rel_err(run_onnx(onnx_path, x), model_predict(loaded, i, x), net.out_scale) <= 1e-5


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc is not installed")
def test_c_exports_the_activation(act_model, tmp_path):
    _, path = act_model
    net, loaded, i = load_deploy_net(path)
    _, c = write_c(net, tmp_path)
    x = synthetic_x(2000)
    err = rel_err(run_c(c, x, 5), model_predict(loaded, i, x), net.out_scale)
    assert err <= 1e-5
    # the activation matters on these inputs: the same weights with ReLU give other outputs
    net.activation = "relu"
    assert rel_err(net.forward(x), model_predict(loaded, i, x), net.out_scale) > 1e-3


@pytest.mark.parametrize("fmt", ["c-int8", "firmware"])
def test_int8_and_firmware_refuse_by_name(act_model, tmp_path, fmt):
    act, path = act_model
    with pytest.raises(AnytipError, match=f"--format {fmt} supports ReLU networks only.*'{act}'"):
        export_model(path, fmt, tmp_path / fmt, rows=200, embedded_checks=False)


def test_other_activations_are_refused(tmp_path):
    path = save_baseline(tmp_path, config=MLPConfig(sizes=(8, 12, 5), activation="tanh"))
    with pytest.raises(AnytipError, match="activation 'tanh'"):
        load_deploy_net(path)
