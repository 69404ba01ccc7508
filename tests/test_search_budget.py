"""The microcontroller budget model: parameter and MAC counts, estimates against the compiled
C, constraints in Optuna's convention, budget files with clear errors."""

import pytest

from anytip.deploy.embedded import toolchain_missing
from anytip.errors import AnytipError
from anytip.search.budget import constraints, cost, estimate, fits, load_budget, measure, params_and_macs

PAPER = (8, 12, 64, 64, 5)


@pytest.fixture(scope="module")
def budget():
    return load_budget("stm32f334")


def test_paper_mlp_counts():
    assert params_and_macs(PAPER) == (5425, 5280)


def test_budget_file(budget):
    assert budget.flash_bytes_max == 24 * 1024 and budget.ram_bytes_max == 2048
    assert budget.inference_s_max == pytest.approx(1e-3)


def test_bad_budget_names_file_and_key(tmp_path):
    path = tmp_path / "b.yaml"
    path.write_text("name: x\nclock_hz: -1\nflash_total_bytes: 1\nflash_bytes_max: 1\n"
                    "ram_bytes_max: 1\nsample_rate_hz: 200\ninference_fraction_max: 0.2\nflsh: 3\n")
    with pytest.raises(AnytipError, match=r"b.yaml.*clock_hz.*flsh' is not allowed"):
        load_budget(path)
    with pytest.raises(AnytipError, match="known budgets: .*stm32f334"):
        load_budget("nope")


def test_paper_mlp_fits_and_a_wide_one_does_not(budget):
    assert fits(estimate(PAPER, budget), budget)
    flash, ram, time = constraints(estimate((8, 64, 128, 128, 5), budget), budget)
    assert flash > 0 and ram < 0


@pytest.mark.skipif(toolchain_missing() is not None, reason=str(toolchain_missing()))
@pytest.mark.parametrize("sizes", [PAPER, (8, 32, 32, 5), (8, 24, 48, 48, 5), (8, 16, 5),
                                   (8, 32, 64, 64, 32, 5)])
def test_estimate_tracks_the_compiled_code(budget, sizes):
    m, e = measure(sizes, budget), estimate(sizes, budget)
    assert m.measured_sizes and not e.measured_sizes
    assert abs(m.flash_bytes - e.flash_bytes) <= 0.03 * m.flash_bytes
    assert abs(m.ram_bytes - e.ram_bytes) <= 64
    if m.measured_instructions:
        assert abs(m.instructions - e.instructions) <= 0.12 * m.instructions
    assert cost(sizes, budget).measured_sizes


def test_activation_costs_and_libm_activations_refused(budget):
    relu, hs = estimate(PAPER, budget), estimate(PAPER, budget, "hardswish")
    assert hs.instructions > estimate(PAPER, budget, "leaky_relu").instructions > relu.instructions
    assert hs.activation == "hardswish" and hs.macs == relu.macs
    with pytest.raises(AnytipError, match="'tanh' does not export.*leaky_relu"):
        cost(PAPER, budget, activation="tanh")


@pytest.mark.skipif(toolchain_missing() is not None, reason=str(toolchain_missing()))
@pytest.mark.parametrize("activation", ["leaky_relu", "hardswish"])
def test_activation_code_is_compiled_and_counted(budget, activation):
    sizes = (8, 32, 32, 5)
    m, r, e = measure(sizes, budget, activation=activation), measure(sizes, budget), estimate(sizes, budget,
                                                                                            activation)
    assert m.activation == activation and m.flash_bytes > r.flash_bytes
    if m.measured_instructions:
        assert m.instructions > r.instructions
        assert abs(m.instructions - e.instructions) <= 0.12 * m.instructions
