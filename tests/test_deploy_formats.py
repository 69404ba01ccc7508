"""ONNX, C float32 and C int8 exports of a baseline and a folded cross-sensor model, verified."""

from __future__ import annotations

import json
import re

import numpy as np
import onnx
import pytest

from anytip.deploy import quantize as quantize_mod
from anytip.deploy.c_export import write_c
from anytip.deploy.c_int8 import pack_pairs
from anytip.deploy.export import export_model
from anytip.deploy.native import run_c
from anytip.deploy.net import load_deploy_net, model_predict
from anytip.deploy.onnx_export import run_onnx, write_onnx
from anytip.deploy.quantize import quantize, refine_rounding, simulate
from anytip.errors import AnytipError
from test_deploy_helpers import save_baseline, save_folded, synthetic_x

needs_gcc = pytest.mark.skipif(__import__("shutil").which("gcc") is None, reason="gcc is not installed")


@pytest.fixture(autouse=True)
def quick_rounding_search(monkeypatch):
    """A short rounding search keeps these tests at seconds (the search itself is tested below)."""
    monkeypatch.setattr(quantize_mod, "REFINE", ((0, 1, 300), (-1, 1, 300)))


@pytest.fixture(params=["baseline", "folded"])
def model_path(request, tmp_path):
    return save_baseline(tmp_path) if request.param == "baseline" else save_folded(tmp_path)


def rel_err(y, ref, scale):
    return float((np.abs(y - ref).max(0) / scale).max())


def test_onnx_is_self_contained_dynamic_and_matches(model_path, tmp_path):
    net, loaded, i = load_deploy_net(model_path)
    path = write_onnx(net, tmp_path)
    m = onnx.load(str(path), load_external_data=False)
    assert m.opset_import[0].version >= 18
    assert not any(t.data_location == onnx.TensorProto.EXTERNAL for t in m.graph.initializer)
    assert m.graph.input[0].type.tensor_type.shape.dim[0].dim_param == "batch"
    x = synthetic_x()
    assert rel_err(run_onnx(path, x), model_predict(loaded, i, x), net.out_scale) <= 1e-5
    assert run_onnx(path, x[:1]).shape == (1, 5)


@needs_gcc
def test_c_float_matches_and_uses_no_heap_or_libm(model_path, tmp_path):
    net, loaded, i = load_deploy_net(model_path, unit=None)
    h, c = write_c(net, tmp_path)
    header, source = h.read_text(), c.read_text()
    assert "#define ANYTIP_N_INPUTS 8" in header and "#define ANYTIP_N_OUTPUTS 5" in header
    assert "void anytip_infer(const float *in, float *out);" in header
    assert not re.search(r"malloc|free\(|#include <math|fmaxf|expf|sqrtf", source)
    assert "static const float P[" in source
    x = synthetic_x()
    assert rel_err(run_c(c, x, 5), model_predict(loaded, i, x), net.out_scale) <= 1e-5


@needs_gcc
def test_int8_c_equals_its_numpy_model_and_stays_close(model_path, tmp_path):
    r = export_model(model_path, "c-int8", tmp_path, rows=800, embedded_checks=False)
    assert r["gcc_host_vs_numpy_int8"]["max_abs_err"] == [0.0] * 5
    assert "static const uint32_t W0[" in (tmp_path / "anytip_model.c").read_text()
    net, loaded, i = load_deploy_net(model_path)
    x = synthetic_x(2000, seed=1)
    q = quantize(net, x[:1000])
    assert all(L.q_w.dtype == np.int8 and np.abs(L.q_w).max() <= 127 for L in q.layers)
    err = simulate(q, x[1000:]) - model_predict(loaded, i, x[1000:])
    assert np.sqrt((err ** 2).mean(0)).max() / net.out_scale.min() < 0.1  # bounded, in output stds
    assert r["accuracy"]["against"] == "float model (no targets)"


def test_rounding_search_lowers_the_error_against_float(tmp_path):
    net, _, _ = load_deploy_net(save_baseline(tmp_path))
    x = synthetic_x(600, seed=2)
    q = quantize(net, x)
    rows = x[::2][:300]  # the rows the search scores
    before = float((((simulate(q, rows) - net.forward(rows)) / net.out_scale) ** 2).mean())
    after = refine_rounding(q, net, x, layer=0, passes=1, rows=300)
    assert after < before
    assert np.abs(q.layers[0].q_w.astype(int)).max() <= 127


@pytest.mark.parametrize("layer", [0, 1, 2, 3])
def test_rounding_search_scores_moves_as_the_whole_network_would(tmp_path, layer):
    """The search scores each move by rank-one updates; its loss equals a full int8 forward pass."""
    net, _, _ = load_deploy_net(save_baseline(tmp_path))
    x = synthetic_x(800, seed=3)
    q = quantize(net, x)
    rows = x[np.unique(np.linspace(0, len(x) - 1, 200).round().astype(int))]

    def loss() -> float:
        return float((((simulate(q, rows) - net.forward(rows)) / net.out_scale) ** 2).mean())

    before = loss()
    after = refine_rounding(q, net, x, layer=layer, passes=1, rows=200)
    assert after == pytest.approx(loss(), rel=1e-9) and after <= before


def test_affine_refit_brings_each_layer_closer_to_the_float_network(tmp_path, monkeypatch):
    net, _, _ = load_deploy_net(save_baseline(tmp_path))
    x = synthetic_x(1000, seed=4)
    monkeypatch.setattr(quantize_mod, "REFINE", ())
    errs = {}
    for refit in (False, True):
        monkeypatch.setattr(quantize_mod, "REFIT", refit)
        errs[refit] = float(((simulate(quantize(net, x), x) - net.forward(x)) ** 2).mean())
    assert errs[True] < errs[False]


def test_int8_words_hold_each_weight_once():
    q_w = np.random.default_rng(0).integers(-127, 128, (7, 5)).astype(np.int8)
    b = pack_pairs(q_w).view(np.int8)  # little-endian: the four bytes of each word in order
    assert b.size == 8 * 6  # padded to even inputs and outputs
    assert sorted(b.tolist()) == sorted(q_w.ravel().tolist() + [0] * (48 - 35))
    assert b[0] == q_w[0, 0] and b[1] == q_w[0, 1] and b[2] == q_w[1, 0] and b[3] == q_w[1, 1]


@needs_gcc
@pytest.mark.parametrize("fmt", ["onnx", "c", "firmware", "model"])
def test_every_format_writes_a_passing_report(model_path, tmp_path, fmt):
    r = export_model(model_path, fmt, tmp_path / fmt, unit=None, rows=800, embedded_checks=False)
    saved = json.loads((tmp_path / fmt / "verification.json").read_text())
    assert saved["passed"] and r["passed"] and saved["format"] == fmt
    assert saved["reference"]["source"] == "synthetic" and "input scaler" in saved["reference"]["note"]


def test_registry_rows_are_the_reference_when_the_unit_is_there(small_registry, tmp_path):
    unit = small_registry.units()[0]
    path = save_baseline(tmp_path, n=1)
    meta = json.loads(path.with_suffix(".json").read_text())
    meta["meta"]["unit_ids"] = [unit]
    path.with_suffix(".json").write_text(json.dumps(meta))
    r = export_model(path, "onnx", tmp_path / "o", registry=small_registry, rows=500)
    assert r["reference"]["source"] == "registry" and r["reference"]["rows"] > 0 and r["passed"]
    assert r["scores"]["force_rmse_n"] > 0
    q = export_model(path, "c-int8", tmp_path / "q", registry=small_registry, rows=500, embedded_checks=False)
    acc = q["accuracy"]
    assert acc["against"] == "targets" and set(acc["rmse_increase"]) == {"force_rmse_n", "angle_rmse_rad"}
    assert abs(acc["rmse_increase"]["force_rmse_n"]) < 0.05  # a random model: int8 changes little


def test_unknown_unit_and_format_are_clear_errors(tmp_path):
    path = save_baseline(tmp_path)
    with pytest.raises(AnytipError, match="unit 'X9' is not in the model file"):
        export_model(path, "onnx", tmp_path / "o", unit="X9")
    with pytest.raises(AnytipError, match="--format 'tflite'"):
        export_model(path, "tflite", tmp_path / "o")


def test_cli_export_all_formats(tmp_path):
    from anytip.cli import main

    path = save_folded(tmp_path)
    assert main(["export", str(path), "--unit", "N2", "--format", "all", "--out", str(tmp_path / "all"),
                 "--no-embedded", "--rows", "800", "--registry", str(tmp_path / "none")]) == 0
    for fmt in ("onnx", "c", "c-int8", "firmware"):
        assert json.loads((tmp_path / "all" / fmt / "verification.json").read_text())["unit"] == "N2"
    assert main(["export", str(path), "--unit", "nope", "--format", "c", "--out", str(tmp_path / "x")]) == 2


def test_heteroscedastic_model_is_scored_on_its_means_against_registry_rows(small_registry, tmp_path):
    """A model with 5 means and 5 log-variance outputs: RMSE uses the means, int8 calibrates
    the scale outputs by their own spread, and every output is verified."""
    from anytip.models.heteroscedastic import hetero_config, output_scaler_2d
    from anytip.models.io import save_models
    from anytip.models.mlp import BatchedMLP, MLPConfig
    from anytip.uncertainty.ensembles import hetero_meta
    from test_deploy_helpers import scalers

    unit = small_registry.units()[0]
    in_s, out_s = scalers(1, 0)
    model = BatchedMLP(1, hetero_config(MLPConfig()), seed=3)
    path = save_models(tmp_path / "h" / "model.safetensors", model, in_s, output_scaler_2d(out_s),
                       {"unit_ids": [unit], **hetero_meta(5, 0.5)})
    for fmt in ("c", "c-int8"):
        r = export_model(path, fmt, tmp_path / fmt, registry=small_registry, rows=500, embedded_checks=False)
        assert r["passed"] and r["reference"]["source"] == "registry", fmt
        assert len(r["output_scale"]) == 10 and r["scores"]["force_rmse_n"] > 0
