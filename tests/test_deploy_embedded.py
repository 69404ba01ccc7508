"""Cortex-M4F measures of the C exports: cross-compiled sizes and emulated instruction counts."""

from __future__ import annotations

import numpy as np
import pytest

from anytip.deploy import embedded
from anytip.deploy.export import export_model
from anytip.deploy.native import fma_flags
from test_deploy_helpers import save_baseline, save_folded

pytestmark = pytest.mark.skipif(embedded.emulator_missing() is not None,
                                reason=str(embedded.emulator_missing()))

KB = 1024


@pytest.fixture(scope="module")
def paper_model(tmp_path_factory):
    return save_baseline(tmp_path_factory.mktemp("m"), n=1)


def test_float32_meets_the_budget_and_runs_on_the_m4(paper_model, tmp_path):
    r = export_model(paper_model, "c", tmp_path, rows=200)
    m4 = r["cortex_m4"]
    assert r["passed"] and m4["emulated_vs_host"]["passed"]
    assert m4["flash_bytes"] <= 24 * KB and m4["ram_bytes"] <= 2 * KB
    assert m4["rodata"] >= 4 * r["params"]  # every weight is in flash as a float32
    assert m4["instructions_per_mac"] > 1.0  # at least one instruction per multiply-accumulate
    assert m4["macs"] == 8 * 12 + 12 * 64 + 64 * 64 + 64 * 5
    if fma_flags():  # the host build fuses like the device: the same sums, bit for bit
        assert m4["emulated_vs_host"]["max_rel_err"] == 0.0


def test_int8_meets_the_budget_and_matches_on_the_m4(paper_model, tmp_path):
    r = export_model(paper_model, "c-int8", tmp_path, rows=200)
    m4 = r["cortex_m4"]
    assert m4["flash_bytes"] <= 8 * KB and m4["ram_bytes"] <= 2 * KB
    # the int8 C turns off contraction, so the device rounds every step like the host and numpy
    assert m4["emulated_vs_host"]["max_rel_err"] == 0.0


def test_folded_model_measures_like_the_baseline(tmp_path):
    r = export_model(save_folded(tmp_path), "c", tmp_path / "c", unit="N1", rows=200)
    assert r["passed"] and r["cortex_m4"]["flash_bytes"] <= 24 * KB


def test_instruction_count_scales_with_the_model(tmp_path):
    from anytip.models.mlp import MLPConfig

    small = save_baseline(tmp_path / "s", n=1, config=MLPConfig(sizes=(8, 8, 5)))
    r = export_model(small, "c", tmp_path / "c", rows=100)
    big = export_model(save_baseline(tmp_path / "b", n=1), "c", tmp_path / "b" / "c", rows=100)
    assert r["cortex_m4"]["instructions"] < big["cortex_m4"]["instructions"] / 10
    assert np.isfinite(r["cortex_m4"]["instructions_per_mac"])


def test_float32_c_executes_fewer_instructions_than_a_peer_compiler(paper_model, tmp_path):
    """Against a reference measured here, on the same model, compiler and emulator: the
    ONNX-to-C generator emx-onnx-cgen (2.2x more instructions in reports/deploy)."""
    from anytip.deploy.export import prepare
    from anytip.deploy.peers import measure_peer, peer_missing

    if peer_missing("emx-onnx-cgen"):
        pytest.skip(peer_missing("emx-onnx-cgen"))
    ours = export_model(paper_model, "c", tmp_path / "ours", rows=50)["cortex_m4"]
    p = prepare(paper_model, rows=50)
    peer = measure_peer("emx-onnx-cgen", p.loaded, p.index, p.net, p.ref, p.y_model, tmp_path / "peer")
    assert peer["gcc_host"]["passed"]
    assert ours["instructions"] < 0.7 * peer["cortex_m4"]["instructions"]
    assert ours["flash_bytes"] <= peer["cortex_m4"]["flash_bytes"]
    assert ours["ram_bytes"] < peer["cortex_m4"]["ram_bytes"]
