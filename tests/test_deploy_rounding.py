"""Export verification by error bounds: the float32 rounding bound holds, adapts to the network and
its inputs (no tolerance tuned to one fleet), and a changed weight fails verification."""

from __future__ import annotations

import re
import shutil

import numpy as np
import onnx
import pytest
from onnx import numpy_helper

from anytip.deploy.c_export import write_c
from anytip.deploy.export import errors, verify_c, verify_onnx
from anytip.deploy.net import DeployNet, load_deploy_net, model_predict
from anytip.deploy.onnx_export import write_onnx
from anytip.deploy.reference import synthetic_reference
from anytip.deploy.rounding import U_FLOAT32, error_bound, gamma, network_tolerance
from test_deploy_helpers import save_baseline, save_folded

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc is not installed")


def random_net(rng: np.random.Generator, sizes=(8, 12, 64, 64, 5), in_scale=1e-3, bias=0.5) -> DeployNet:
    layers = [(rng.normal(0, 1 / np.sqrt(i), (i, o)) * (in_scale if k == 0 else 1), rng.normal(0, bias, o))
              for k, (i, o) in enumerate(zip(sizes[:-1], sizes[1:], strict=True))]
    n = sizes[-1]
    return DeployNet(layers, False, np.zeros(n), np.ones(n), np.zeros(sizes[0]), np.ones(sizes[0]))


def test_gamma_is_the_textbook_bound():
    assert gamma(1, U_FLOAT32) == pytest.approx(U_FLOAT32, rel=1e-6)
    assert gamma(65, U_FLOAT32) > 65 * U_FLOAT32
    with pytest.raises(ValueError):
        gamma(2**24, U_FLOAT32)


@pytest.mark.parametrize("activation", ["relu", "leaky_relu", "hardswish"])
def test_float32_forward_stays_within_the_bound_on_random_networks(activation):
    """A float32 evaluation (numpy, another summation order than C or onnxruntime) of many random
    networks, with inputs of the magnitudes of raw and tared pressures, never leaves the bound."""
    rng = np.random.default_rng(0)
    worst = 0.0
    for trial in range(20):
        net = random_net(rng, in_scale=10.0 ** rng.uniform(-5, -2), bias=rng.uniform(0.01, 3))
        net.activation = activation
        x = rng.normal(0, 10.0 ** rng.uniform(1, 5), (256, 8))
        bound = network_tolerance(net, x)
        err = np.abs(net.forward(x, np.float32) - net.forward(x))
        assert (err <= bound).all(), trial
        worst = max(worst, float((err / bound).max()))
    assert 1e-4 < worst < 1  # the bound is not vacuous: errors reach a visible part of it


def test_the_bound_grows_with_cancellation():
    """The same output from a sum of large opposite terms has a wider bound (the old fixed 1e-5
    relative tolerance ignored this and failed on other registries' models)."""
    W = np.array([[1.0], [-1.0]])
    x_small = np.array([[1.0, 0.5]])
    x_large = np.array([[1e6 + 1.0, 1e6 + 0.5]])
    layer = [(W, np.zeros(1), None)]
    assert error_bound(layer, x_large)[0, 0] > 1e5 * error_bound(layer, x_small)[0, 0]


def _fixture(tmp_path, kind):
    path = save_baseline(tmp_path) if kind == "baseline" else save_folded(tmp_path)
    net, loaded, i = load_deploy_net(path)
    ref = synthetic_reference(net, 500)
    return net, ref, model_predict(loaded, i, ref.x)


@pytest.mark.parametrize("kind", ["baseline", "folded"])
def test_onnx_passes_and_reports_error_against_bound(tmp_path, kind):
    net, ref, y_model = _fixture(tmp_path, kind)
    rep = verify_onnx(write_onnx(net, tmp_path), net, ref, y_model)
    assert rep["parameters"]["passed"] and rep["parameters"]["count"] == net.n_params
    check = rep["onnxruntime"]
    assert check["passed"] and 0 < check["max_err_over_bound"] <= 1
    assert len(check["max_bound"]) == net.n_outputs


def _onnx_with(path, k, idx, factor):
    model = onnx.load(str(path))
    init = next(t for t in model.graph.initializer if t.name == f"W{k}")
    w = numpy_helper.to_array(init).copy()
    w[idx] *= factor
    init.CopyFrom(numpy_helper.from_array(w, f"W{k}"))
    out = path.with_name(f"changed_{k}.onnx")
    onnx.save_model(model, str(out))
    return out


def _sample_weights(net, rng, per_layer=6):
    """Per layer: its smallest and largest weight and a few random ones."""
    for k, (W, _) in enumerate(net.layers):
        flat = np.abs(W).ravel()
        picks = {int(flat.argmin()), int(flat.argmax()), *rng.choice(flat.size, per_layer, replace=False)}
        for p in sorted(picks):
            yield k, np.unravel_index(p, W.shape)


def test_a_1e_4_change_to_any_one_weight_fails_onnx_verification(tmp_path):
    net, ref, y_model = _fixture(tmp_path, "baseline")
    path = write_onnx(net, tmp_path)
    tried = 0
    for k, idx in _sample_weights(net, np.random.default_rng(1)):
        rep = verify_onnx(_onnx_with(path, k, idx, 1 + 1e-4), net, ref, y_model)
        assert not rep["parameters"]["passed"] and rep["parameters"]["differing"] == 1, (k, idx)
        tried += 1
    assert tried >= 4 * 7


def _c_with(source, position, factor):
    text = source.read_text()

    table = re.search(r"static const float P\[\d+\] = \{(.*?)\};", text, re.S)
    literals = list(re.finditer(r"[-+]?[0-9.]+e[-+]?[0-9]+f", table.group(1)))
    lit = literals[position]
    value = np.float32(float(lit.group()[:-1]) * factor)
    start = table.start(1) + lit.start()
    changed = text[:start] + f"{float(value):.8e}f" + text[start + len(lit.group()):]
    out = source.with_name(f"changed_{position}.c")
    out.write_text(changed)
    return out


@needs_gcc
def test_c_passes_and_a_1e_4_change_to_any_one_weight_fails(tmp_path):
    net, ref, y_model = _fixture(tmp_path, "folded")
    _, source = write_c(net, tmp_path)
    rep = verify_c(source, net, ref, y_model)
    assert rep["parameters"]["passed"] and rep["gcc_host"]["passed"]
    assert 0 < rep["gcc_host"]["max_err_over_bound"] <= 1
    rng = np.random.default_rng(2)
    for position in rng.choice(net.n_params, 6, replace=False):
        changed = verify_c(_c_with(source, int(position), 1 + 1e-4), net, ref, y_model)
        assert not changed["parameters"]["passed"], position


@pytest.mark.parametrize("layer", [0, 1, 2, 3])
def test_outputs_alone_catch_a_1e_2_change_of_each_layers_most_used_weight(tmp_path, layer):
    """Outputs are checked on their own too: with every parameter exact, a network computed with
    the weight that carries the largest term of its layer off by 1e-2 leaves the bound (a 1e-4
    change hides within the rounding of its sum; the parameter check above catches that)."""
    net, ref, y_model = _fixture(tmp_path, "baseline")
    h = ref.x
    for W, b in net.layers[:layer]:
        h = np.maximum(h @ W + b, 0)
    W = net.layers[layer][0]
    i, o = np.unravel_index(np.abs(h[:, :, None] * W[None]).max(0).argmax(), W.shape)
    changed = DeployNet([(w.copy(), b.copy()) for w, b in net.layers], net.output_relu, net.out_offset,
                        net.out_scale, net.in_mean, net.in_std)
    changed.layers[layer][0][i, o] *= 1 + 1e-2
    assert errors(net.forward(ref.x, np.float32), y_model, net, ref.x)["passed"]
    assert not errors(changed.forward(ref.x, np.float32), y_model, net, ref.x)["passed"]
